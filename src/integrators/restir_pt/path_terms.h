// ReSTIR PT's path terms (pt_path.h documents the paths): the per-vertex random streams, a walk's
// vertices, the hybrid shift's reconnection criterion, a path's last segment to an emitter and the
// strategies' MIS weight. RESTIR_HD: the walks (walk.h) and the shifts (shift_*.h) of every backend
// compute every term with these functions.
#pragma once
#include "frame/direction_sampling.h"
#include "frame/frame_world.h"
#include "integrators/path/path_pixel.h"
#include "integrators/restir_pt/pt_path.h"

namespace rl {

namespace pt_detail {

// The longest path a walk offers, x_1..x_66 (path.max_depth <= 64, options.cpp): its vertex counts
// are stored in bytes (PathSample).
constexpr int kMaxVertices = 66;

// Per-vertex random streams: vertex d of a walk always uses the same numbers, whatever happened
// before, so random replay regenerates the base path's decisions vertex by vertex.
struct VertexRandoms {
  float nee_select;
  Vec2 nee_point;
  float lobe;
  Vec2 direction;
  float roulette;
};
RESTIR_HD inline VertexRandoms vertex_randoms(uint64_t seed, int vertex) {
  Pcg32 r(mix64(seed ^ (0x9e3779b97f4a7c15ULL * uint64_t(vertex + 1))), uint64_t(vertex) * 2 + 1);
  VertexRandoms v;
  v.nee_select = r.next_float();
  v.nee_point = r.next_2d();
  v.lobe = r.next_float();
  v.direction = r.next_2d();
  v.roulette = r.next_float();
  return v;
}

struct Vertex {
  Vec3 p, ng;
  Frame frame;
  Vec3 wo;  // world direction toward the previous vertex
  Bsdf bsdf;
  bool delta = false;
  // What identifies the hit (surface_at): kept by a path whose reconnection vertex it becomes
  // (kInvalidId at the primary vertex, which comes from the G-buffer).
  uint32_t geom = kInvalidId, prim = 0;
  Vec2 barycentrics;
};

RESTIR_HD inline Vertex vertex_from_surface(const GSurface& s) {
  Vertex v;  // no surface record: the primary vertex x_1 is never a reconnection vertex (k >= 2)
  v.p = s.p, v.ng = s.ng, v.frame = s.frame(), v.wo = s.wo, v.bsdf = s.bsdf, v.delta = bsdf_is_delta(s.bsdf);
  return v;
}

RESTIR_HD inline Vertex vertex_from_hit(const PathWorld& world, const SurfaceInteraction& si, Vec3 wo) {
  const MaterialParams& m = world.scene.materials[si.material];
  Vertex v{si.p, si.ng, Frame::from_normal(si.ns), wo, make_bsdf(m, material_reflectance(world.scene, m, si.uv)), false, si.geom,
           si.prim, si.barycentrics};
  v.delta = bsdf_is_delta(v.bsdf);
  return v;
}

RESTIR_HD inline uint32_t emitter_of(const PathWorld& world, const SurfaceInteraction& si) {
  return world.lights.emitter_at(si);
}

RESTIR_HD inline bool rough(const Vertex& v, float threshold) { return !v.delta && bsdf_roughness(v.bsdf) >= threshold; }

// Delta lobes of mixed BSDFs (a smooth coat over a diffuse base): a vertex whose path continues
// through a delta lobe ("delta event") is never a reconnection vertex's end. Reconnecting from it
// would evaluate the BSDF's non-delta lobes (bsdf_eval) for a path sampled through the delta: a
// path of another measure (one solid-angle dimension fewer), which no Jacobian maps -- biased. So
// the hybrid shift's criterion (GRIS §7.2) asks, of both x_{k-1} and x_k, a rough BSDF AND a
// non-delta event: x_{k-1}'s toward x_k, x_k's toward x_{k+1} (ReSTIR PT's reference keeps the
// sampled lobe in its path flags for the same reason, Lin et al. 2022, supplement). Whether an
// event is a delta is a property of the path (a direction exactly on the mirror), not of the random
// numbers, so the offset path's own walk gets the same answer. Single-lobe BSDFs: the event is a
// delta exactly when the BSDF is.

// The hybrid shift's reconnection criterion for a vertex pair a = x_{k-1}, b = x_k, `distance` apart
// along the unit direction `dir` (a -> b), in two parts: pair_opens decides everything but b's own
// event, pair_completes that (b's event toward `b_out`, known a step later). Neither's event may be
// a delta (the callers check those). `thr`: the footprint threshold of the path's own primary hit
// (footprint_threshold; 0 under roughness-distance).
//  - pt.reconnection = roughness-distance (GRIS §7.2): both vertices rough, |x_k - x_{k-1}| >=
//    pt.distance_threshold.
//  - pt.reconnection = footprint (ReSTIR PT Enhanced, Lin, Kettunen, Wyman 2026, sec. 4, eq. 5):
//        min( (p_{k-1}(ω_{k-1}) G(x_{k-1} -> x_k))^-1, (p_k(ω_k) G(x_k -> x_{k-1}))^-1 )
//            >= c/100 · |x_0 - x_1|² / (<n_{x_1}, x̂_1x_0> / 4π),   and   α(x_{k-1}) >= α_min (sec. 4.2),
//    with p_i the solid-angle density of direction sampling at x_i (given its incoming direction),
//    G(a -> b) = |cos θ_b| / |a - b|² (the cosine at the receiving vertex, geometric normal), c =
//    pt.footprint_threshold (0.02), α_min = pt.footprint_min_roughness. The left terms are the
//    area a sample of the lobe at x_{k-1} represents around x_k (the forward ray footprint) and the
//    one of x_k's lobe, traced back, around x_{k-1} (the inverse ray footprint); the right side is
//    the area a uniform 1/(4π) lobe at the camera would represent at x_1 (the primary footprint).
//    The inverse footprint is not tested for a diffuse or emissive x_k (fn. 6), nor the forward one
//    for an emitter at infinity or a delta light (no area density: counting measure or direction).
RESTIR_HD inline float primary_footprint(const GSurface& s) {
  const float c = std::fabs(dot(s.ng, s.wo));
  return s.depth * s.depth * (4 * kPi) / (c > 1e-6f ? c : 1e-6f);
}
RESTIR_HD inline float footprint_threshold(const PathSettings& ps, const GSurface& s) {
  return ps.pt.reconnection == Reconnection::footprint ? ps.pt.footprint_threshold / 100 * primary_footprint(s) : 0.0f;
}
// (p G)^-1 >= thr with G = cos / d², as d² >= thr p cos (no division: p cos = 0 is an infinite footprint).
RESTIR_HD inline bool footprint_at_least(float distance, float pdf, float cos_receiver, float thr) {
  return distance * distance >= thr * pdf * cos_receiver;
}
// Density of direction sampling at v toward dir (v.wo the incoming direction): the walk's st.pdf
// before roulette, recomputed the same way wherever a criterion needs it.
RESTIR_HD inline float pdf_toward(const PathSettings& ps, const Vertex& v, Vec3 dir) {
  return direction_pdf(v.bsdf, ps.path.bsdf_sampling, v.frame.to_local(v.wo), v.frame.to_local(dir));
}
RESTIR_HD inline bool footprint_mode(const PathSettings& ps) { return ps.pt.reconnection == Reconnection::footprint; }
RESTIR_HD inline bool pdf_proxy(const PathSettings& ps) { return ps.pt.roughness_proxy == RoughnessProxy::pdf; }
// Whether the criterion at a vertex depends on the direction the path reaches it from, so that the
// offset path, which reaches x_k from y_{k-1}, must test it again (shift_hybrid.h): the inverse
// footprint, and the pdf proxy's roughness of x_k.
RESTIR_HD inline bool criterion_depends_on_direction(const PathSettings& ps) { return footprint_mode(ps) || pdf_proxy(ps); }
// Whether v counts as rough (>= threshold) for a pair that leaves it toward dir (v.wo the incoming
// direction): never for a delta BSDF; else its roughness parameter (rough()), or under
// pt.roughness_proxy = pdf the black-box proxy of ReSTIR PT Enhanced's supplement (§4, eq. 26),
//     1 / p_v(ω)² >= α_min,
// p_v the solid-angle density of direction sampling at v (pdf_toward: the marginal over lobes, as
// the footprints use, supplement §3). A GGX lobe's peak density 1/(4π α²) gives 16π² α⁴: 0.2 is met
// from α ≈ 0.19, the roughness the material threshold asks. A diffuse lobe (p <= 1/π) is always
// rough (π² > 1, the thresholds' upper bound). Compared as p² α_min <= 1 (p = 0: no density, rough).
RESTIR_HD inline bool proxy_rough(const Vertex& v, float pdf, float threshold) { return !v.delta && pdf * pdf * threshold <= 1; }
RESTIR_HD inline bool rough_toward(const PathSettings& ps, const Vertex& v, Vec3 dir, float threshold) {
  return pdf_proxy(ps) ? proxy_rough(v, pdf_toward(ps, v, dir), threshold) : rough(v, threshold);
}
// The footprint criterion's test at x_{k-1} (a): α_min and the forward footprint toward b along dir,
// `cos_b` the cosine at b; the pdf proxy reads the same density as the footprint, computed once.
RESTIR_HD inline bool opens_footprint(const PathSettings& ps, const Vertex& a, Vec3 dir, float distance, float cos_b, float thr) {
  if (!pdf_proxy(ps)) return rough(a, ps.pt.footprint_min_roughness) && footprint_at_least(distance, pdf_toward(ps, a, dir), cos_b, thr);
  const float p = pdf_toward(ps, a, dir);
  return proxy_rough(a, p, ps.pt.footprint_min_roughness) && footprint_at_least(distance, p, cos_b, thr);
}
// Whether pair_completes tests anything (else an open pair is reconnectable as soon as b's event is
// not a delta): the inverse footprint, or the pdf proxy at x_k under roughness-distance; neither
// for a diffuse x_k, which passes both.
RESTIR_HD inline bool inverse_tested(const PathSettings& ps, const Vertex& b) {
  return criterion_depends_on_direction(ps) && b.bsdf.type != Material::Type::diffuse;
}
// Under roughness-distance with the pdf proxy, x_k's roughness needs its outgoing direction: it is
// pair_completes' test.
RESTIR_HD inline bool pair_opens(const PathSettings& ps, const Vertex& a, const Vertex& b, Vec3 dir, float distance, float thr) {
  if (!footprint_mode(ps))
    return rough_toward(ps, a, dir, ps.pt.roughness_threshold) && (pdf_proxy(ps) || rough(b, ps.pt.roughness_threshold)) &&
           distance >= ps.pt.distance_threshold;
  return opens_footprint(ps, a, dir, distance, std::fabs(dot(b.ng, dir)), thr);
}
// b.wo must be -dir (the incoming direction at x_k from x_{k-1}).
RESTIR_HD inline bool pair_completes(const PathSettings& ps, const Vertex& b, Vec3 a_ng, Vec3 dir, float distance, Vec3 b_out, float thr) {
  if (!inverse_tested(ps, b)) return true;
  if (!footprint_mode(ps)) return rough_toward(ps, b, b_out, ps.pt.roughness_threshold);
  return footprint_at_least(distance, pdf_toward(ps, b, b_out), std::fabs(dot(a_ng, dir)), thr);
}
// The same for an emitter vertex after v (normal: its geometric normal, zero for delta lights),
// reached by a non-delta event (emitters are diffuse or delta: always rough, no inverse footprint;
// the environment and distant lights are infinitely far).
// `nee`: the emitter was drawn by next-event estimation; under pt.force_nee_reconnection such a
// light vertex is always reconnectable from a non-delta x_{n-1} (ReSTIR PT Enhanced, sec. 6.2.3:
// "the NEE light vertex is forced to be the reconnection vertex if no earlier one exists"). The
// rule reads the path's strategy tag, which every shift keeps, so the offset path's own walk
// decides the same (PathSettings::force_nee_one_sided plants the bias of a base-only rule).
RESTIR_HD inline bool emitter_reconnectable(const PathSettings& ps, const Vertex& v, bool is_direction, Vec3 normal, Vec3 dir,
                                            float distance, float thr, bool nee) {
  if (nee && ps.pt.force_nee_reconnection) return true;
  if (!footprint_mode(ps)) return rough_toward(ps, v, dir, ps.pt.roughness_threshold) && (is_direction || distance >= ps.pt.distance_threshold);
  if (is_direction) return rough_toward(ps, v, dir, ps.pt.footprint_min_roughness);
  return opens_footprint(ps, v, dir, distance, std::fabs(dot(normal, dir)), thr);
}

// The last segment of a path: from vertex v to an emitter point (position = direction for the
// environment and distant lights). Everything the contribution and the strategies' densities need.
// A delta light's vertex is a fixed point (point, spot) or direction (distant) whatever the
// receiver, so a shift that reconnects to it has Jacobian 1 (counting measure), as for the
// environment's direction; what changes is the emission toward the new receiver (a spot's falloff,
// 1 / d²), which eval_terminal recomputes.
struct Terminal {
  Rgb fcos{0};          // f_s(v) |cos| toward the emitter
  Rgb emission{0};      // Le (point, spot: the intensity toward v; distant: L)
  float geometry = 0;   // area: |cos_l| / d²; point, spot: 1 / d²; environment, distant: 1
  float light_pdf = 0;  // density of Lights::sample_point at the emitter point (its own measure)
  float bsdf_pdf = 0;   // density of the direction sampling at v, in the emitter's measure
  float measure = 0;    // solid angle at v -> the emitter's measure (area: |cos_l| / d²; env: 1; delta lights: 0)
  Vec3 wi;              // direction from v to the emitter
  Ray shadow;
};

// `sampled`: the emitter point was just drawn by sample_point, which gave its density (pdf) and,
// for the environment, its radiance: they are used instead of looking them up again (the same
// values bit for bit). The environment's texel lookups were a fifth of a ReSTIR PT frame.
struct SampledEmitter {
  float pdf = 0;
  Rgb env_radiance{0};
};

RESTIR_HD inline Terminal eval_terminal(const PathWorld& world, const PathSettings& ps, const Vertex& v, uint32_t emitter,
                                        Vec3 pos, Vec3 normal, const SampledEmitter* sampled = nullptr) {
  Terminal t;
  const float eps = world.ray_epsilon;
  float to_measure = 1;
  bool have_pdf = sampled != nullptr;
  switch (world.lights.kind(emitter)) {
    case LightKind::environment:
      t.wi = pos;
      if (sampled) {
        t.emission = sampled->env_radiance;
      } else {
        const LightsView::EnvironmentValue env = world.lights.environment_value(t.wi);
        t.emission = env.radiance;
        t.light_pdf = env.pdf;
        have_pdf = true;
      }
      t.geometry = 1;
      t.shadow = spawn_ray(v.p, v.ng, t.wi, eps);
      break;
    case LightKind::distant:
      t.wi = pos;
      t.emission = world.lights.delta_emission(emitter, t.wi);
      t.geometry = 1;
      to_measure = 0;  // BSDF sampling never reaches a delta light
      t.shadow = spawn_ray(v.p, v.ng, t.wi, eps);
      break;
    case LightKind::point:
    case LightKind::spot: {
      const Vec3 d = pos - v.p;
      const float d2 = length_squared(d);
      if (!(d2 > 0)) return t;
      t.wi = d / std::sqrt(d2);
      t.emission = world.lights.delta_emission(emitter, t.wi);
      t.geometry = 1 / d2;
      to_measure = 0;  // BSDF sampling never reaches a delta light
      t.shadow = spawn_ray_to(v.p, v.ng, pos, Vec3(0), eps);
      break;
    }
    default: {
      const Vec3 d = pos - v.p;
      const float d2 = length_squared(d);
      if (!(d2 > 0)) return t;
      t.wi = d / std::sqrt(d2);
      t.emission = world.lights.emitted(emitter, normal, -t.wi);
      t.geometry = std::fabs(dot(normal, t.wi)) / d2;
      to_measure = t.geometry;
      t.shadow = spawn_ray_to(v.p, v.ng, pos, normal, eps);
      break;
    }
  }
  const Vec3 wo_l = v.frame.to_local(v.wo), wi_l = v.frame.to_local(t.wi);
  t.fcos = bsdf_eval(v.bsdf, wo_l, wi_l) * std::fabs(wi_l.z);
  if (sampled) t.light_pdf = sampled->pdf;
  else if (!have_pdf) t.light_pdf = world.lights.point_pdf(emitter, pos);
  t.measure = to_measure;
  t.bsdf_pdf = direction_pdf(v.bsdf, ps.path.bsdf_sampling, wo_l, wi_l) * to_measure;
  return t;
}

// Balance-heuristic weight of the strategy that produced the last vertex (Veach 1997, eq. 9.10);
// a strategy that is off (no NEE, delta vertex) leaves the other with weight 1. `delta`: the vertex
// is a delta BSDF, or the path reached the emitter through a delta lobe (which NEE cannot sample).
RESTIR_HD inline float strategy_weight(const PathSettings& ps, bool nee_tag, bool delta, float light_pdf, float bsdf_pdf) {
  const bool nee_on = ps.path.nee && !delta;
  if (!nee_on) return nee_tag ? 0.0f : 1.0f;
  const float den = light_pdf + bsdf_pdf;
  if (!(den > 0)) return 0;
  return (nee_tag ? light_pdf : bsdf_pdf) / den;
}

}  // namespace pt_detail

}  // namespace rl
