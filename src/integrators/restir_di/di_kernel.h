// ReSTIR DI's per-sample functions over device-shaped views (RESTIR_HD: the host's DI and, once
// ported, the CUDA backend's run the same code): a light point seen from a G-buffer surface, the
// DI integrand, the shadow ray and the light strategy's density. di_sampling.h documents them.
#pragma once
#include "core/rng.h"
#include "frame/gbuffer.h"
#include "frame/light_tiles.h"
#include "scene/lights_view.h"

namespace rl {

// 16 bytes: the point's normal is not stored but derived from its emitter (LightsView::normal_at),
// so that a ReSTIR DI reservoir is 32 bytes, the size of RTXDI's packed reservoir (Wyman and
// Panteleev 2021, §5; RTXDI's RTXDI_PackedDIReservoir).
struct LightPoint {
  Vec3 position;               // on the emitter; the direction itself for the environment and distant lights
  uint32_t emitter = kNoEmitter;
};
// The sample's identity for the duplication map (reservoir_chain.h): reuse copies a light point
// bit for bit (the identity shift).
RESTIR_HD inline uint64_t duplicate_key(const LightPoint& y) { return hash_point(y.position, y.emitter); }

namespace di_detail {

// Light point y as seen from surface s: the direction (world and shading frame), the radiance
// arriving along it and g, the geometry factor of the DI integrand -- |cos θ_l| / d² for area
// emitters, 1 / d² for point and spot lights, 1 for the environment and distant lights -- which is
// also the Jacobian from solid angle at s to y's sample measure (area, counting, solid angle: Veach
// 1997 §8.2.2.2; for the delta lights it only scales, as no BSDF density converts through it).
// Computed once per candidate and shared by the target, the BSDF strategy's pdf and the shadow ray.
// A spot's intensity depends on the direction to s, so a reused spot sample is re-evaluated at
// every receiver (as its 1 / d² is).
struct LightView {
  Vec3 wi, wi_l;
  Vec3 n;  // the emitter's geometric normal at y (LightsView::normal_at; zero for points and the environment)
  Rgb le{0};
  float g = 0;
};

// false: y sends nothing toward s (degenerate distance, back of a one-sided emitter, black).
RESTIR_HD inline bool view_light(const LightsView& lights, const GSurface& s, const LightPoint& y, LightView& v) {
  switch (lights.kind(y.emitter)) {
    case LightKind::environment:
      v.wi = y.position;
      v.le = lights.environment_radiance(v.wi);
      v.g = 1;
      break;
    case LightKind::distant:
      v.wi = y.position;
      v.le = lights.delta_emission(y.emitter, v.wi);
      v.g = 1;
      break;
    case LightKind::point:
    case LightKind::spot: {
      const Vec3 d = y.position - s.p;
      const float d2 = length_squared(d);
      if (!(d2 > 0)) return false;
      v.wi = d / std::sqrt(d2);
      v.le = lights.delta_emission(y.emitter, v.wi);
      v.g = 1 / d2;
      break;
    }
    default: {
      const Vec3 d = y.position - s.p;
      const float d2 = length_squared(d);
      if (!(d2 > 0)) return false;
      v.wi = d / std::sqrt(d2);
      v.n = lights.normal_at(y.emitter, y.position);
      v.le = lights.emitted(y.emitter, v.n, -v.wi);
      v.g = std::fabs(dot(v.n, v.wi)) / d2;
      break;
    }
  }
  if (is_black(v.le)) return false;
  v.wi_l = s.frame().to_local(v.wi);
  return true;
}

// f(wo, wi) |cos θ_s| Le g, given wo in the shading frame.
RESTIR_HD inline Rgb di_value(const GSurface& s, Vec3 wo_l, const LightView& v) {
  const Rgb f = bsdf_eval(s.bsdf, wo_l, v.wi_l) * std::fabs(v.wi_l.z);
  const Rgb value = f * v.le * v.g;
  return is_finite(value) ? max(value, Rgb(0)) : value;  // non-finite: reported by the render driver, never hidden
}

// The ray that tests the visibility of y from s.
RESTIR_HD inline Ray di_shadow_ray(const LightsView& lights, const GSurface& s, const LightPoint& y, const LightView& v, float eps) {
  switch (lights.kind(y.emitter)) {
    case LightKind::environment:
    case LightKind::distant: return spawn_ray(s.p, s.ng, v.wi, eps);
    case LightKind::point:
    case LightKind::spot: return spawn_ray_to(s.p, s.ng, y.position, Vec3(0), eps);
    default: return spawn_ray_to(s.p, s.ng, y.position, v.n, eps);
  }
}

// Density of the light strategy at y for the receiver s (selection pmf x Lights::sample_emitter's
// density), in y's sample measure.
RESTIR_HD inline float light_density(const LightsView& lights, const GSurface& s, const LightPoint& y, const LightView& v) {
  if (lights.is_delta(y.emitter)) return lights.selection_pmf(y.emitter);  // counting measure
  return lights.pdf(y.emitter, s.p, y.position, v.n) * v.g;
}

}  // namespace di_detail

// The DI integrand at s for light point y, without visibility (di_sampling.h).
RESTIR_HD inline Rgb di_unshadowed(const LightsView& lights, const GSurface& s, const LightPoint& y, float eps, Ray* shadow_ray) {
  if (!s.valid || y.emitter == kNoEmitter) return Rgb(0);
  di_detail::LightView v;
  if (!di_detail::view_light(lights, s, y, v)) return Rgb(0);
  if (shadow_ray) *shadow_ray = di_detail::di_shadow_ray(lights, s, y, v, eps);
  return di_detail::di_value(s, s.frame().to_local(s.wo), v);
}

}  // namespace rl
