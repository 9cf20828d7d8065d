// The ssr integrator's per-pixel code (ssr_frame.h drives it), RESTIR_HD over views, so that every
// backend runs the same stages (issue 48): the reflection rays a pixel traces through the screen,
// Stachowiak's resolve, and the temporal blend with the reprojected history.
#pragma once
#include <algorithm>
#include <cmath>

#include "core/rng.h"
#include "core/sampling.h"
#include "frame/options.h"
#include "frame/reuse_pixel.h"
#include "integrators/ssr/ssr_march.h"
#include "scene/bsdf.h"
#include "scene/lights_view.h"

namespace rl {

// One reflection ray a pixel traced, kept for the resolve of its neighbours.
struct ReflectionRay {
  bool valid = false;  // a direction was drawn
  bool hit = false;    // it landed on a pixel (else: fallback)
  Vec3 dir;            // world direction
  Vec3 hit_p;          // the surface point it landed on
  Rgb radiance{0};     // what it returned: the landed pixel's lit colour, the fallback or nothing
  Rgb weight{0};       // f |cos| / pdf at the pixel that traced it
  float pdf = 0;       // solid-angle pdf of dir (0: a delta lobe)
};

// Nearest integer, halves away from zero (std::lround; the device's lroundf).
RESTIR_HD inline int round_to_int(float v) {
#if defined(__CUDA_ARCH__)
  return int(lroundf(v));
#else
  return int(std::lround(v));
#endif
}

// Neighbours a pixel may reuse rays from in the resolve: similar surfaces only, so that rays do
// not leak across silhouettes (the thresholds of the ReSTIR integrators' defaults).
inline constexpr float kResolveDepth = 0.1f, kResolveNormalDeg = 25.0f;

// What the stages of one pixel sample read: the options, this frame's camera, G-buffer, pyramid
// and lit colours, and the rays traced (ssr.rays per pixel).
struct SsrPixelView {
  SsrOptions so;
  PerspectiveCamera camera;
  GBufferView g;
  HiZView hiz;
  const Rgb* lit;
  const ReflectionRay* traced;
  LightsView lights;
  float extent;       // the scene's diagonal: how far a reflection ray is marched at most
  float ray_epsilon;  // offset of the rays leaving a surface
  RESTIR_HD bool reflective(const GSurface& sf) const { return sf.valid && bsdf_roughness(sf.bsdf) <= so.roughness_cutoff; }
};

// One reflection ray of surface sf: a BSDF sample (GGX importance sampling of the visible normals
// for glossy lobes, the mirror direction for smooth ones), marched through the depth buffer; a hit
// returns the lit colour of the pixel it lands on, a miss the environment (ssr.fallback) or nothing.
RESTIR_HD inline ReflectionRay trace_reflection(const SsrPixelView& v, const GSurface& sf, Pcg32& rng) {
  ReflectionRay r;
  BsdfSample bs;
  const float u_lobe = rng.next_float();
  const Vec2 u = rng.next_2d();
  const Frame shading = sf.frame();
  if (!bsdf_sample(sf.bsdf, shading.to_local(sf.wo), u_lobe, u, bs) || !(bs.pdf > 0)) return r;
  r.valid = true;
  r.weight = bs.f * (std::fabs(bs.wi.z) / bs.pdf);
  r.pdf = bs.is_delta ? 0.0f : bs.pdf;
  r.dir = shading.to_world(bs.wi);
  // A transmitted direction sees nothing the screen shows (glass): the fallback.
  if (dot(r.dir, sf.ng) * dot(sf.wo, sf.ng) >= 0) {
    const Ray ray = spawn_ray(sf.p, sf.ng, r.dir, v.ray_epsilon);
    const SsrOptions& so = v.so;
    const MarchResult m = so.hi_z ? march_hiz(v.camera, v.g, v.hiz, ray.o, r.dir, v.extent, so.max_steps, so.thickness)
                                  : march_linear(v.camera, v.g, v.hiz, ray.o, r.dir, v.extent, so.max_steps, so.thickness);
    if (m.hit) {
      const size_t q = size_t(m.y) * size_t(v.g.width) + size_t(m.x);
      r.hit = true;
      r.hit_p = v.g.pixels[q].p;
      r.radiance = v.lit[q];
      return r;
    }
  }
  if (v.so.fallback == SsrFallback::environment) r.radiance = v.lights.environment_radiance(r.dir);
  return r;
}

// Reflected radiance at pixel (x, y): the mean of its own rays' f cos/pdf x L, or with the resolve
// (Stachowiak 2015, "Stochastic screen-space reflections", SIGGRAPH Advances in Real-Time
// Rendering), a ratio estimator over its own and its neighbours' rays: each weighted by this
// pixel's BRDF x cosine over the pdf it was drawn with, normalised by the sum of the weights and
// scaled by this pixel's directional albedo (its own rays' mean f cos/pdf). rng: the pixel's
// neighbour stream.
RESTIR_HD inline Rgb reflected(const SsrPixelView& v, int x, int y, Pcg32& rng) {
  const SsrOptions& so = v.so;
  const size_t rays = size_t(so.rays), p = size_t(y) * size_t(v.g.width) + size_t(x);
  const GSurface sf = v.g.surface(p);
  Rgb own(0), albedo(0);
  for (size_t i = 0; i < rays; ++i) {
    const ReflectionRay& r = v.traced[p * rays + i];
    own += r.weight * r.radiance;
    albedo += r.weight;
  }
  own /= float(rays);
  albedo /= float(rays);
  if (so.resolve_neighbors == 0 || bsdf_is_delta(sf.bsdf)) return own;
  const Frame shading = sf.frame();
  const Vec3 wo = shading.to_local(sf.wo);
  Rgb num(0);
  float den = 0;
  const auto reuse = [&](const ReflectionRay& r) {  // weight: this pixel's BRDF x cos over r's pdf
    if (!r.valid || !(r.pdf > 0)) return;
    const Vec3 d = r.hit ? normalize(r.hit_p - sf.p) : r.dir;
    const Vec3 wi = shading.to_local(d);
    const float wgt = luminance(bsdf_eval(sf.bsdf, wo, wi)) * std::fabs(wi.z) / r.pdf;
    if (!(wgt > 0) || !std::isfinite(wgt)) return;
    num += r.radiance * wgt;
    den += wgt;
  };
  for (size_t i = 0; i < rays; ++i) reuse(v.traced[p * rays + i]);
  // The neighbourhood shrinks with the lobe (Stachowiak 2015 scales the resolve kernel with the
  // BRDF's footprint): a near-mirror's neighbours' rays point outside its lobe and only add noise.
  const float radius = so.resolve_radius * std::min(1.0f, bsdf_roughness(sf.bsdf) / std::max(so.roughness_cutoff, 1e-3f));
  for (int k = 0; k < so.resolve_neighbors && radius >= 0.5f; ++k) {
    const Vec2 d = sample_uniform_disk_concentric(rng.next_2d()) * radius;
    const int nx = x + round_to_int(d.x), ny = y + round_to_int(d.y);
    if ((nx == x && ny == y) || nx < 0 || ny < 0 || nx >= v.g.width || ny >= v.g.height) continue;
    const size_t q = size_t(ny) * size_t(v.g.width) + size_t(nx);
    if (!similar_surfaces(sf, v.g.pixels[q], kResolveDepth, kResolveNormalDeg)) continue;
    for (size_t i = 0; i < rays; ++i) reuse(v.traced[q * rays + i]);
  }
  return den > 0 ? albedo * (num / den) : own;
}

// Mean distance from pixel p's surface to where its reflection rays landed (the scene's extent
// when none landed: the reflection of something far away, e.g. the sky).
RESTIR_HD inline float reflection_distance(const SsrPixelView& v, size_t p) {
  const size_t rays = size_t(v.so.rays);
  const Vec3 at = v.g.pixels[p].p;
  float sum = 0;
  int n = 0;
  for (size_t i = 0; i < rays; ++i)
    if (v.traced[p * rays + i].hit) sum += length(v.traced[p * rays + i].hit_p - at), ++n;
  return n > 0 ? sum / float(n) : v.extent;
}

// The history of reflective pixel (x, y): the previous frame's colour where its reflection was,
// filtered bilinearly over the previous pixels that show this reflector; false where there is none.
RESTIR_HD inline bool reflection_history(const SsrPixelView& v, const PerspectiveCamera& previous_camera, const GPacked* previous_g,
                                         const Rgb* history, int x, int y, Rgb& out) {
  const size_t p = size_t(y) * size_t(v.g.width) + size_t(x);
  const GPacked& sf = v.g.pixels[p];
  // Where the previous frame showed this reflection: a reflection moves with its virtual image --
  // the reflected point seen through the surface, the view ray extended by the rays' hit distance
  // -- not with the surface (parallax-corrected reprojection, as in Stachowiak 2015). The reflector
  // must be the same surface there (normals agree, and it lies on this one's tangent plane).
  // Through the pixel's centre, not its jittered sample, so that a still camera finds the same
  // pixel and a moving one filters the same way whatever the jitter.
  const Vec3 cam = v.camera.position();
  const Vec3 view = v.camera.generate_ray({float(x) + 0.5f, float(y) + 0.5f}).d;
  const Vec3 virtual_point = cam + view * (length(sf.p - cam) + reflection_distance(v, p));
  const GMotion motion = v.g.motion_at(x, y);
  const Vec3 moved = motion.p_previous + (virtual_point - sf.p);  // with the reflector's own motion
  // A nearest-pixel fetch under motion aliases: its choice of pixel jumps with the jitter.
  Vec2 r;
  if (!previous_camera.project(moved, r)) return false;
  const float fx = r.x - 0.5f, fy = r.y - 0.5f;
  const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
  Rgb sum(0);
  float weight = 0;
  for (int k = 0; k < 4; ++k) {
    const int hx = x0 + (k & 1), hy = y0 + (k >> 1);
    if (hx < 0 || hy < 0 || hx >= v.g.width || hy >= v.g.height) continue;
    const size_t q = size_t(hy) * size_t(v.g.width) + size_t(hx);
    const GSurface before = unpack_surface(previous_g[q], v.g.materials, previous_camera.position());
    if (!v.reflective(before) || dot(before.ns, motion.ns_previous) < std::cos(kResolveNormalDeg * kPi / 180.0f) ||
        std::fabs(dot(before.p - motion.p_previous, motion.ns_previous)) > 0.02f * before.depth)  // on this reflector's plane
      continue;
    const float w = ((k & 1) ? fx - float(x0) : 1 - (fx - float(x0))) * ((k >> 1) ? fy - float(y0) : 1 - (fy - float(y0)));
    sum += history[q] * w;
    weight += w;
  }
  if (!(weight > 1e-3f)) return false;
  out = sum / weight;
  return true;
}

// ssr.temporal at pixel (x, y): a reflective pixel blends with its history where the reprojected
// surface is the same and the history's colour is within this frame's 3x3 neighbourhood range
// (neighbourhood clamping, Karis 2014, "High-quality temporal supersampling"), so that what the
// reflection showed a frame ago cannot linger. current: this frame before the blend.
RESTIR_HD inline Rgb temporal_pixel(const SsrPixelView& v, const PerspectiveCamera& previous_camera, const GPacked* previous_g,
                                    const Rgb* history, const Rgb* current, float alpha, int x, int y) {
  const size_t p = size_t(y) * size_t(v.g.width) + size_t(x);
  Rgb h;
  if (!v.reflective(v.g.surface(p)) || !reflection_history(v, previous_camera, previous_g, history, x, y, h)) return current[p];
  Rgb lo(kInfinity), hi(-kInfinity);
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int nx = std::min(std::max(x + dx, 0), v.g.width - 1), ny = std::min(std::max(y + dy, 0), v.g.height - 1);
      const Rgb c = current[size_t(ny) * size_t(v.g.width) + size_t(nx)];
      lo = min(lo, c);
      hi = max(hi, c);
    }
  h = max(lo, min(hi, h));
  return h + (current[p] - h) * alpha;
}

}  // namespace rl
