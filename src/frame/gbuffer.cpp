#include "frame/gbuffer.h"

#include <algorithm>
#include <array>
#include <span>

#include "core/parallel.h"
#include "integrators/path/path_tracer.h"
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

void fill_gsurface(const RenderContext& ctx, const Ray& ray, const Hit* hit, GSurface& s, const std::vector<Mat4>* back,
                   GMotion* motion) {
  fill_gsurface(ctx.accel.scene_view(), ctx.lights.view(), ray, hit, s, back ? back->data() : nullptr, back ? uint32_t(back->size()) : 0,
                motion);
}

// The primary hits of a frame: camera rays tile by tile (parallel_for_tiles' 16x16 pixels, one
// Embree stream call), traced as a coherent batch -- Embree turns neighbouring camera rays into
// packets, which traverse the BVH once for several rays -- then each pixel's surface. The hits
// are one scalar query per pixel's to float precision (tests/test_gbuffer.cpp): bit for bit on triangles but where a ray
// meets two at one point; Embree's packet sphere test rounds the last bits differently. The tiles
// are fixed, so the G-buffer does not depend on the thread count. (The wavefront path tracer's
// camera rays have gone through the same packets since issue 9.)
void build_gbuffer(const RenderContext& ctx, const PerspectiveCamera& camera, int frame, int sample, GBuffer& g) {
  const std::vector<Mat4> back = motion_back(ctx.scene, frame);
  g.resize(camera.width(), camera.height(), !back.empty());  // motion only where something can move
  parallel_for_tiles(g.width, g.height, [&](int x0, int y0, int x1, int y1) {
    std::array<Ray, kPixelTile * kPixelTile> rays;
    std::array<Hit, kPixelTile * kPixelTile> hits;
    size_t n = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) rays[n++] = camera_ray(ctx, camera, x, y, frame, sample);
    ctx.accel.intersect(std::span<const Ray>(rays.data(), n), std::span<Hit>(hits.data(), n), true);
    n = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x, ++n) {
        const size_t i = size_t(y) * size_t(g.width) + size_t(x);
        fill_gsurface(ctx, rays[n], hits[n].valid() ? &hits[n] : nullptr, g.pixels[i], &back, g.motion_slot(i));
      }
  });
}

}  // namespace rl
