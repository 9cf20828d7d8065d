#include "integrators/gbuffer.h"

#include "core/parallel.h"
#include "integrators/path_tracer.h"
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

void fill_gsurface(const RenderContext& ctx, const Ray& ray, const Hit* hit, GSurface& s, const std::vector<Mat4>* back) {
  fill_gsurface(ctx.accel.scene_view(), ctx.lights.view(), ray, hit, s, back ? back->data() : nullptr, back ? uint32_t(back->size()) : 0);
}

void build_gbuffer(const RenderContext& ctx, const PerspectiveCamera& camera, int frame, int sample, GBuffer& g) {
  g.width = camera.width();
  g.height = camera.height();
  g.pixels.resize(size_t(g.width) * size_t(g.height));  // no clearing: fill_gsurface writes every entry
  const std::vector<Mat4> back = motion_back(ctx.scene, frame);
  parallel_for_pixels(g.width, g.height, [&](int x, int y) {
    Ray ray = camera_ray(ctx, camera, x, y, frame, sample);
    Hit hit;
    const bool found = ctx.accel.intersect(ray, hit);
    fill_gsurface(ctx, ray, found ? &hit : nullptr, g.pixels[size_t(y) * size_t(g.width) + size_t(x)], &back);
  });
}

}  // namespace rl
