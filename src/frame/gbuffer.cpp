#include "frame/gbuffer.h"

#include <algorithm>
#include <array>
#include <span>

#include "core/parallel.h"
#include "backends/cpu/accel.h"
#include "frame/pixel_sampler.h"
#include "scene/texture.h"

namespace rl {

std::vector<Mat4> motion_back(const Scene& scene, int frame) {
  std::vector<Mat4> back(scene.animations.size());
  for (size_t a = 0; a < back.size() && frame > 0; ++a) {
    Mat4 inv;
    if (scene.animations[a].transform(frame).inverse(inv)) back[a] = scene.animations[a].transform(frame - 1) * inv;
  }
  return back;
}

// The primary hits of a frame: camera rays tile by tile (parallel_for_tiles' 16x16 pixels, one
// Embree stream call), traced as a coherent batch -- Embree turns neighbouring camera rays into
// packets, which traverse the BVH once for several rays -- then each pixel's surface. The hits
// are one scalar query per pixel's to float precision (tests/frame/test_gbuffer.cpp): bit for bit on triangles but where a ray
// meets two at one point; Embree's packet sphere test rounds the last bits differently. The tiles
// are fixed, so the G-buffer does not depend on the thread count. (The wavefront path tracer's
// camera rays have gone through the same packets since issue 9.)
void build_gbuffer(const RenderContext& ctx, const PerspectiveCamera& camera, int frame, int sample, const Mat4* back,
                   uint32_t back_count, GPacked* pixels, Rgb* emitted, GMotion* motion) {
  const int width = camera.width();
  const CameraSampling cs = camera_sampling(ctx.options);
  const SceneView& scene = ctx.accel.scene_view();
  const LightsView& lights = ctx.lights.view();
  parallel_for_tiles(width, camera.height(), [&](int x0, int y0, int x1, int y1) {
    std::array<Ray, kPixelTile * kPixelTile> rays;
    std::array<Hit, kPixelTile * kPixelTile> hits;
    size_t n = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) rays[n++] = camera_ray(cs, camera, x, y, frame, sample);
    ctx.accel.intersect(std::span<const Ray>(rays.data(), n), std::span<Hit>(hits.data(), n), true);
    n = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x, ++n) {
        const size_t i = size_t(y) * size_t(width) + size_t(x);
        fill_gpacked(scene, lights, rays[n], hits[n].valid() ? &hits[n] : nullptr, pixels[i], emitted[i], back, back_count,
                     motion ? motion + i : nullptr);
      }
  });
}

void build_gbuffer(const RenderContext& ctx, const PerspectiveCamera& camera, int frame, int sample, GBuffer& g) {
  const std::vector<Mat4> back = motion_back(ctx.scene, frame);
  g.resize(camera.width(), camera.height(), !back.empty());  // motion only where something can move
  const SceneView& sv = ctx.accel.scene_view();
  g.materials.assign(sv.materials, sv.materials + sv.material_count);
  g.eye = camera.position();
  build_gbuffer(ctx, camera, frame, sample, back.data(), uint32_t(back.size()), g.pixels.data(), g.emitted.data(),
                g.motion_data() ? g.motion.data() : nullptr);
}

}  // namespace rl
