// ReSTIR GI's per-pixel pieces (restir_gi.cpp documents the method), RESTIR_HD over device-shaped
// views and a Tracer (di_pixel.h): the sample, its integrand and target, the reconnection shift's
// bridge in a scene where nothing moves, the initial sample and the direct light. The CPU's
// restir-gi runs them on Embree, the CUDA backend's kernels (gi_frame.h) on its BVH.
#pragma once
#include "frame/gbuffer.h"
#include "integrators/path/path_pixel.h"
#include "frame/reuse_pixel.h"
#include "restir/reservoir.h"
#include "restir/shift.h"

namespace rl {

struct GiSample {
  Vec3 position;      // x_s, or the direction when the ray escaped to the environment
  Vec3 normal;        // geometric normal at x_s
  bool infinite = false;
  Rgb radiance{0};    // reflected L_o(x_s -> visible point), estimated by a path from x_s
  uint32_t geom = kInvalidId, prim = kInvalidId;  // the surface of x_s (its animation moves it)
  Pcg32 suffix;       // the random stream of the path that estimated `radiance` (replayed across frames)
};
using GiReservoir = restir::Reservoir<GiSample>;

// f_s(wo, wi) |cos| L_o at visible surface s for sample x (no visibility).
RESTIR_HD inline Rgb gi_integrand(const GSurface& s, const GiSample& x) {
  if (!s.valid) return Rgb(0);
  Vec3 wi = x.position;
  if (!x.infinite) {
    const Vec3 d = x.position - s.p;
    const float len = length(d);
    if (!(len > 0)) return Rgb(0);
    wi = d / len;
  }
  const Frame shading = s.frame();
  const Vec3 wo_l = shading.to_local(s.wo), wi_l = shading.to_local(wi);
  const Rgb v = bsdf_eval(s.bsdf, wo_l, wi_l) * std::fabs(wi_l.z) * x.radiance;
  return is_finite(v) ? max(v, Rgb(0)) : v;  // non-finite: reported by the render driver, never hidden
}

// The target: luminance of the integrand (gi.target = contribution) or of the cached radiance
// (radiance), times visibility of x_s from s when asked.
template <class Tracer>
RESTIR_HD float gi_target_in(const PathWorld& w, const Tracer& tracer, GiTarget kind, const GSurface& s, const GiSample& x,
                             bool visibility) {
  const Rgb v = gi_integrand(s, x);
  if (is_black(v)) return 0;
  if (visibility) {
    const float eps = w.ray_epsilon;
    const Ray r = x.infinite ? spawn_ray(s.p, s.ng, x.position, eps) : spawn_ray_to(s.p, s.ng, x.position, x.normal, eps);
    if (tracer.occluded(r)) return 0;
  }
  return luminance(kind == GiTarget::radiance ? x.radiance : v);
}

// Solid angle at `from` -> at `to` for the same sample point (1 for the environment; ReSTIR GI eq. 11).
RESTIR_HD inline float gi_jacobian(const GiSample& x, Vec3 from, Vec3 to) {
  return x.infinite ? 1.0f : restir::reconnection_jacobian(from, to, x.position, x.normal);
}

// The bridge of mis.h for GI where nothing moves: the reconnection shift (x_s kept, its cached
// radiance with it) and each domain's target at its own visible point.
template <class Tracer>
struct GiViewBridge {
  const PathWorld* world;
  const Tracer* tracer;
  GiTarget kind;
  const GSurface* const* surfaces;
  RESTIR_HD bool shift_to_canonical(int i, const GiSample& y, GiSample& x, float& jacobian) const {
    x = y;
    jacobian = gi_jacobian(y, surfaces[i]->p, surfaces[0]->p);
    return jacobian > 0;
  }
  // Another domain's stored target is p̂_i(y) at its own visible point, visibility included (this
  // scene: nothing moves, so last frame's history too), and the shift keeps x = y with
  // |∂T_{0→i}/∂x| = 1 / |∂T_{i→0}/∂y| (ReSTIR GI eq. 11 both ways). So combine() reads p̂_i(y) /
  // jacobian (mis.h) instead of tracing domain i's shadow ray to x again.
  RESTIR_HD bool stored_target_valid(int i) const { return i > 0; }
  RESTIR_HD float target_from(int i, const GiSample& x) const {
    const float t = gi_target_in(*world, *tracer, kind, *surfaces[i], x, true);
    return i == 0 ? t : t * gi_jacobian(x, surfaces[0]->p, surfaces[i]->p);
  }
};

// One BSDF-sampled secondary hit and the radiance leaving it toward s (a path of `path` bounces,
// path.max_depth = the integrator's - 1). A delta lobe gets no sample: a plain path estimate goes
// to `specular` instead.
template <class Tracer>
RESTIR_HD GiReservoir gi_initial_in(const PathWorld& w, const Tracer& tracer, const PathOptions& path, GiTarget kind, const GSurface& s,
                                    Pcg32& rng, Rgb& specular) {
  GiReservoir r;
  r.confidence = 1;
  if (!s.valid) return r;
  BsdfSample bs;
  const float u_lobe = rng.next_float();
  const Vec2 u = rng.next_2d();
  const Frame shading = s.frame();
  const Vec3 wo_l = shading.to_local(s.wo);
  if (!bsdf_sample(s.bsdf, wo_l, u_lobe, u, bs) || !(bs.pdf > 0) || is_black(bs.f)) return r;
  const Vec3 wi = shading.to_world(bs.wi);
  const Ray ray = spawn_ray(s.p, s.ng, wi, w.ray_epsilon);
  if (bs.is_delta) {  // no NEE and no reconnection through a delta lobe: a plain path estimate
    specular = bs.f * std::fabs(bs.wi.z) / bs.pdf * path_radiance_in(w, tracer, path, ray, rng);
    return r;
  }
  GiSample x;
  x.suffix = rng;  // the stream path_radiance draws from, for replays in other frames
  x.radiance = path_radiance_in(w, tracer, path, ray, rng, /*skip_first_emission=*/true);
  Hit hit;
  float pdf = bs.pdf;
  if (tracer.intersect(ray, hit)) {
    const SurfaceInteraction si = surface_interaction(w.scene, ray, hit);
    x.position = si.p;
    x.normal = si.ng;
    x.geom = si.geom;
    x.prim = si.prim;
    // The sample is valued along the direction from the visible point to x_s (as every shift
    // sees it), so its density is taken there too: the traced ray left from an offset origin, and
    // near contact (x_s within a few epsilons) the two directions differ enough to bias f/p.
    const Vec3 wi_pos = normalize(si.p - s.p);
    pdf = bsdf_pdf(s.bsdf, wo_l, shading.to_local(wi_pos));
  } else {
    x.infinite = true;
    x.position = wi;
  }
  const float t = gi_target_in(w, tracer, kind, s, x, false);  // visible: it was traced
  if (pdf > 0) restir::stream(r, x, t, t / pdf, rng.next_float());
  restir::finalize(r);
  return r;
}

// Direct light at a non-delta visible point: one light sample (no MIS: the GI samples exclude
// emission, so light sampling is the only strategy for it).
template <class Tracer>
RESTIR_HD Rgb gi_direct_in(const PathWorld& w, const Tracer& tracer, const GSurface& s, Pcg32& rng) {
  if (!s.valid || bsdf_is_delta(s.bsdf)) return Rgb(0);
  LightSample ls;
  const float u_select = rng.next_float();
  const Vec2 u = rng.next_2d();
  if (!w.lights.sample(s.p, u_select, u, ls) || !(ls.pdf > 0)) return Rgb(0);
  const Frame shading = s.frame();
  const Vec3 wi_l = shading.to_local(ls.wi);
  const Rgb f = bsdf_eval(s.bsdf, shading.to_local(s.wo), wi_l) * std::fabs(wi_l.z);
  if (is_black(f)) return Rgb(0);
  return tracer.occluded(shadow_ray_to_light(s.p, s.ng, ls, w.ray_epsilon)) ? Rgb(0) : f * ls.radiance / ls.pdf;
}

// A pixel's radiance: emission seen, the specular and direct estimates, and f(x) W of its sample.
RESTIR_HD inline Rgb gi_shade(const GSurface& sf, const GiReservoir& r, Rgb specular) {
  Rgb L = sf.valid ? sf.le + specular : sf.le;
  if (sf.valid && r.has_sample()) L += gi_integrand(sf, r.sample) * r.ucw;  // visible: the target included it
  mark_non_finite(r, L);
  return L;
}

}  // namespace rl
