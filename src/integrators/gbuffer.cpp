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
  s = GSurface{};
  if (!hit) {
    s.background = ctx.lights.environment_radiance(ray.d);
    return;
  }
  SurfaceInteraction si = ctx.accel.interaction(ray, *hit);
  s.valid = true;
  s.p = si.p;
  s.ng = si.ng;
  s.ns = si.ns;
  s.frame = Frame::from_normal(si.ns);
  s.wo = -ray.d;
  s.depth = hit->t;
  const Material& mat = ctx.scene.materials[size_t(si.material)];
  s.bsdf = make_bsdf(mat, material_reflectance(ctx.scene, mat, si.uv));
  uint32_t e = si.is_sphere ? ctx.lights.sphere_emitter(si.prim) : ctx.lights.triangle_emitter(si.geom, si.prim);
  if (e != kNoEmitter) s.emitted = ctx.lights.emitted(e, si.ng, s.wo);
  s.p_previous = s.p;
  s.ns_previous = s.ns;
  const int a = si.is_sphere ? ctx.scene.spheres[si.prim].animation : ctx.scene.meshes[si.geom].animation;
  if (back && a >= 0 && size_t(a) < back->size()) {
    s.p_previous = (*back)[size_t(a)].apply_point(s.p);
    s.ns_previous = normalize((*back)[size_t(a)].apply_vector(s.ns));  // rigid: the rotation part
  }
}

void build_gbuffer(const RenderContext& ctx, const PerspectiveCamera& camera, int frame, int sample, GBuffer& g) {
  g.width = camera.width();
  g.height = camera.height();
  g.pixels.assign(size_t(g.width) * size_t(g.height), GSurface{});
  const std::vector<Mat4> back = motion_back(ctx.scene, frame);
  parallel_for_pixels(g.width, g.height, [&](int x, int y) {
    Ray ray = camera_ray(ctx, camera, x, y, frame, sample);
    Hit hit;
    const bool found = ctx.accel.intersect(ray, hit);
    fill_gsurface(ctx, ray, found ? &hit : nullptr, g.pixels[size_t(y) * size_t(g.width) + size_t(x)], &back);
  });
}

bool reproject(const PerspectiveCamera& previous, Vec3 p, int& x, int& y) {
  Vec2 r;
  if (!previous.project(p, r)) return false;
  x = int(r.x);
  y = int(r.y);
  return x >= 0 && y >= 0 && x < previous.width() && y < previous.height();
}

bool similar_surfaces(const GSurface& a, const GSurface& b, float depth_threshold, float normal_threshold_deg) {
  if (!a.valid || !b.valid) return false;
  if (std::fabs(a.depth - b.depth) > depth_threshold * std::max(a.depth, 1e-6f)) return false;
  return dot(a.ns, b.ns) >= std::cos(normal_threshold_deg * kPi / 180.0f);
}

}  // namespace rl
