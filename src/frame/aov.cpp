#include "frame/aov.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <span>

#include "backends/cpu/accel.h"
#include "core/parallel.h"
#include "frame/gbuffer.h"
#include "frame/pixel_sampler.h"
#include "scene/lights.h"
#include "scene/camera.h"

namespace rl {

void Aovs::resize(int w, int h) {
  width = w, height = h;
  const size_t n = size_t(w) * size_t(h);
  albedo.assign(n, Rgb(0));
  normal.assign(n, Vec3(0));
  depth.assign(n, 0.0f);
  depth_gradient.assign(n, 0.0f);
  motion.assign(n, Vec2{});
  emission.assign(n, Rgb(0));
  surface_id.assign(n, kNoSurface);
}

namespace {

// What a denoiser divides the lighting by (Schied et al. 2017, sec. 4: "demodulate the albedo of
// directly visible surfaces"): the colour the BSDF multiplies incident light by at normal incidence.
Rgb bsdf_albedo(const Bsdf& b) {
  switch (b.type) {
    case Material::Type::diffuse:
    case Material::Type::coated_diffuse:
      return b.reflectance;
    case Material::Type::conductor:
      return b.use_reflectance ? b.reflectance : bsdf_conductor_fresnel(b, 1.0f);
    case Material::Type::dielectric:
      return Rgb(1);
  }
  return Rgb(1);
}

// One pixel's AOVs from its G-buffer entry (fill_gsurface) and hit.
void fill_pixel(const GSurface& s, const GMotion& m, const Hit& hit, const PerspectiveCamera& camera,
                const PerspectiveCamera* previous, uint32_t sphere_geom, Aovs& a, size_t i) {
  if (!s.valid) return;
  a.albedo[i] = bsdf_albedo(s.bsdf);
  a.normal[i] = dot(s.ns, s.wo) < 0 ? -s.ns : s.ns;
  a.depth[i] = dot(s.p - camera.position(), camera.forward());
  a.surface_id[i] = hit.geom == sphere_geom ? sphere_geom + hit.prim : hit.geom;
  // Both raster positions by projection (not the pixel centre the ray went through), so that a
  // still camera gives exactly 0; project sets them whenever the point is in front of the camera.
  Vec2 r, now;
  if (previous && dot(m.p_previous - previous->position(), previous->forward()) > 0 &&
      dot(s.p - camera.position(), camera.forward()) > 0) {
    previous->project(m.p_previous, r);
    camera.project(s.p, now);
    a.motion[i] = {r.x - now.x, r.y - now.y};
  }
}

// depth_gradient: the larger of the x and y derivatives, each the smaller one-sided difference to
// a neighbour on a surface (a silhouette's far side would otherwise give an edge pixel a huge one).
void fill_depth_gradient(Aovs& a) {
  parallel_for_pixels(a.width, a.height, [&](int x, int y) {
    const size_t i = a.index(x, y);
    if (!a.valid(i)) return;
    auto axis = [&](int dx, int dy) {
      float d = kInfinity;
      for (int s : {-1, 1}) {
        const int nx = x + s * dx, ny = y + s * dy;
        if (nx < 0 || ny < 0 || nx >= a.width || ny >= a.height) continue;
        const size_t j = a.index(nx, ny);
        if (a.valid(j)) d = std::min(d, std::fabs(a.depth[j] - a.depth[i]));
      }
      return d == kInfinity ? 0.0f : d;
    };
    a.depth_gradient[i] = std::max(axis(1, 0), axis(0, 1));
  });
}

// The emission AOV: the mean over the frame's own camera samples (camera_ray: the integrators' sample
// pattern, pixel filter, seed and spp) of the radiance each primary ray sees emitted (GSurface::le:
// an emitter's, or the environment's where it escapes). Every integrator adds exactly this at its
// primary hits (path_pixel.h, gbuffer.cpp build the same rays), so colour - emission is the frame's
// reflected light sample for sample. The pixel centre's emission would not be: where an emitter's
// edge crosses a pixel, a jittered sample on the emitter left 30x the light in the "reflected"
// part of a ceiling pixel beside it, which SVGF then spread over the ceiling (relMSE 0.11 -> 0.26
// in scenes/dynamic-room.pbrt, raw 1-spp pt against after SVGF, 320x180, 4 frames).
void fill_sampled_emission(const RenderContext& ctx, const PerspectiveCamera& camera, int frame, const Mat4* back,
                           uint32_t back_count, int x0, int y0, int x1, int y1, Aovs& out) {
  const CameraSampling cs = camera_sampling(ctx.options);
  const SceneView& scene = ctx.accel.scene_view();
  const LightsView& lights = ctx.lights.view();
  const int spp = std::max(1, cs.spp);
  std::array<Ray, kPixelTile * kPixelTile> rays;
  std::array<Hit, kPixelTile * kPixelTile> hits;
  std::array<Rgb, kPixelTile * kPixelTile> sum;
  sum.fill(Rgb(0));
  for (int sample = 0; sample < spp; ++sample) {
    size_t n = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) rays[n++] = camera_ray(cs, camera, x, y, frame, sample);
    ctx.accel.intersect(std::span<const Ray>(rays.data(), n), std::span<Hit>(hits.data(), n), true);
    for (size_t k = 0; k < n; ++k) {
      GPacked g;  // only the emission is read: nothing unpacked
      Rgb le;
      fill_gpacked(scene, lights, rays[k], hits[k].valid() ? &hits[k] : nullptr, g, le, back, back_count, nullptr);
      sum[k] += le;
    }
  }
  size_t n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x, ++n) out.emission[out.index(x, y)] = sum[n] / float(spp);
}

}  // namespace

void build_aovs(const RenderContext& ctx, const PerspectiveCamera& camera, const PerspectiveCamera* previous,
                int frame, Aovs& out) {
  const int width = camera.width(), height = camera.height();
  out.resize(width, height);
  const std::vector<Mat4> back = motion_back(ctx.scene, frame);
  const SceneView& scene = ctx.accel.scene_view();
  const LightsView& lights = ctx.lights.view();
  const uint32_t sphere_geom = ctx.accel.sphere_geom();
  // Tiles of camera rays as one coherent stream, as build_gbuffer traces them (gbuffer.cpp).
  parallel_for_tiles(width, height, [&](int x0, int y0, int x1, int y1) {
    std::array<Ray, kPixelTile * kPixelTile> rays;
    std::array<Hit, kPixelTile * kPixelTile> hits;
    size_t n = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) rays[n++] = camera.generate_ray({float(x) + 0.5f, float(y) + 0.5f});
    ctx.accel.intersect(std::span<const Ray>(rays.data(), n), std::span<Hit>(hits.data(), n), true);
    n = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x, ++n) {
        GSurface s;
        GMotion m;
        const Hit* hit = hits[n].valid() ? &hits[n] : nullptr;
        fill_gsurface(scene, lights, rays[n], hit, s, back.data(), uint32_t(back.size()), &m);
        fill_pixel(s, m, hits[n], camera, previous, sphere_geom, out, out.index(x, y));
      }
    fill_sampled_emission(ctx, camera, frame, back.data(), uint32_t(back.size()), x0, y0, x1, y1, out);
  });
  fill_depth_gradient(out);
}

std::vector<std::pair<std::string, std::vector<float>>> aov_channels(const Aovs& a) {
  std::vector<std::pair<std::string, std::vector<float>>> ch;
  auto add = [&](const char* name, auto get) {
    std::vector<float> v(a.surface_id.size());
    for (size_t i = 0; i < v.size(); ++i) v[i] = get(i);
    ch.emplace_back(name, std::move(v));
  };
  const char* rgb[] = {"R", "G", "B"};
  const char* xyz[] = {"X", "Y", "Z"};
  for (int c = 0; c < 3; ++c) add((std::string("Albedo.") + rgb[c]).c_str(), [&](size_t i) { return a.albedo[i][c]; });
  for (int c = 0; c < 3; ++c) add((std::string("N.") + xyz[c]).c_str(), [&](size_t i) { return a.normal[i][c]; });
  add("Z", [&](size_t i) { return a.depth[i]; });
  add("dZ", [&](size_t i) { return a.depth_gradient[i]; });
  add("Motion.X", [&](size_t i) { return a.motion[i].x; });
  add("Motion.Y", [&](size_t i) { return a.motion[i].y; });
  for (int c = 0; c < 3; ++c) add((std::string("Emission.") + rgb[c]).c_str(), [&](size_t i) { return a.emission[i][c]; });
  add("SurfaceId", [&](size_t i) { return a.valid(i) ? float(a.surface_id[i]) : -1.0f; });
  return ch;
}

}  // namespace rl
