// ReSTIR PT's walks (pt_path.h documents the paths): the per-vertex random streams, one
// direction-sampling step, a walk from the primary hit with every path it offers (NEE connections
// and emitter hits, each MIS-weighted by its strategy), the reconnection vertex a walk chooses, and
// the initial resampling over them. RESTIR_HD over a PathWorld and a Tracer (frame_world.h): every
// backend runs this one implementation of every path density and MIS weight; the shifts
// (shift_*.h) replay and reconnect the same pieces.
#pragma once
#include "frame/direction_sampling.h"
#include "integrators/path/path_pixel.h"
#include "integrators/restir_pt/pt_path.h"
#include "frame/frame_world.h"
#include "frame/light_tiles.h"

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
  int material = -1;  // the hit's material (-1 at the primary vertex, which comes from the G-buffer)
};

RESTIR_HD inline Vertex vertex_from_surface(const GSurface& s) {
  return {s.p, s.ng, s.frame(), s.wo, s.bsdf, bsdf_is_delta(s.bsdf)};
}

RESTIR_HD inline Vertex vertex_from_hit(const PathWorld& world, const SurfaceInteraction& si, Vec3 wo) {
  const MaterialParams& m = world.scene.materials[si.material];
  Vertex v{si.p, si.ng, Frame::from_normal(si.ns), wo, make_bsdf(m, material_reflectance(world.scene, m, si.uv)), false, si.material};
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
// Whether pair_completes tests anything (else an open pair is reconnectable as soon as b's event is
// not a delta).
RESTIR_HD inline bool inverse_tested(const PathSettings& ps, const Vertex& b) {
  return footprint_mode(ps) && b.bsdf.type != Material::Type::diffuse;
}
RESTIR_HD inline bool pair_opens(const PathSettings& ps, const Vertex& a, const Vertex& b, Vec3 dir, float distance, float thr) {
  if (!footprint_mode(ps))
    return rough(a, ps.pt.roughness_threshold) && rough(b, ps.pt.roughness_threshold) && distance >= ps.pt.distance_threshold;
  return rough(a, ps.pt.footprint_min_roughness) && footprint_at_least(distance, pdf_toward(ps, a, dir), std::fabs(dot(b.ng, dir)), thr);
}
// b.wo must be -dir (the incoming direction at x_k from x_{k-1}).
RESTIR_HD inline bool pair_completes(const PathSettings& ps, const Vertex& b, Vec3 a_ng, Vec3 dir, float distance, Vec3 b_out, float thr) {
  if (!inverse_tested(ps, b)) return true;
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
  if (!footprint_mode(ps)) return rough(v, ps.pt.roughness_threshold) && (is_direction || distance >= ps.pt.distance_threshold);
  return rough(v, ps.pt.footprint_min_roughness) &&
         (is_direction || footprint_at_least(distance, pdf_toward(ps, v, dir), std::fabs(dot(normal, dir)), thr));
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

// Next-event estimation from a non-delta vertex v (vertex `vertex` of the walk with stream `seed`):
// the light point, its terminal, its strategy weight m_t and the density the path's candidate
// weight divides by.
//  - pt.nee_candidates = 1: one point of Lights::sample_point with the vertex's numbers u; the
//    density is the point's, light_pdf.
//  - N > 1 (ReSTIR PT Enhanced, Lin, Kettunen, Wyman 2026, sec. 6.1: NEE by RIS inside the path
//    reservoir): N points of sample_point (the first with u, the rest from the vertex's second
//    stream; from the pixel's light tile when the frame drew tiles: nee_candidate), one chosen by
//    resampled importance sampling (Talbot et al. 2005) with the target
//    q = luminance(f_s|cos| Le G) m_t -- the unshadowed contribution from v, the path's prefix being
//    common to all candidates -- and weights w_i = q(X_i) / (N p(X_i)); one shadow ray for the
//    chosen point. Its unbiased contribution weight is W = Σ w_i / q(Y) (GRIS, Lin et al. 2022,
//    eq. 5; Bitterli et al. 2020, eq. 6), so the candidate weight divides by 1/W where one sample
//    divides by p: E[m_t f W] = ∫ m_t f wherever q > 0, which holds where m_t f > 0 (q is f's
//    unshadowed value). m_t stays the balance heuristic of the two strategies' *source* densities
//    (light_pdf, BSDF), which still sum to one over the strategies for every path, so the BSDF
//    strategy's paths that hit an emitter keep their weight unchanged. The chosen point's density
//    has no closed form, so no shift may replay the choice (restir_pt.cpp's check: NEE paths
//    reconnect at their light vertex or before).
// One light point of resampled NEE: from the pixel's light tile when the frame drew tiles (an
// entry's emitter; for the environment, one of the tile's presampled directions with its radiance
// and density), else by Lights::sample_point. Either way it is marginally distributed by
// sample_point's density (light_tiles.h), which ep.pdf is (selection pmf included).
RESTIR_HD inline bool nee_candidate(const LightsView& lights, const LightTileView& tile, float u_select, Vec2 u_point,
                                    EmitterPoint& ep, SampledEmitter& sampled) {
  bool ok;
  if (tile.light_count == 0) {
    ok = lights.sample_point(u_select, u_point, ep, &sampled.env_radiance);
  } else if (const LightTileEntry& en = tile.lights[LightTileView::pick(u_select, tile.light_count)];
             tile.env_count > 0 && en.emitter == lights.environment_emitter()) {
    const EnvTileEntry& d = tile.env[LightTileView::pick(u_point.x, tile.env_count)];
    ep = EmitterPoint{d.direction, Vec3(0), en.emitter, en.pmf * d.pdf};
    sampled.env_radiance = d.radiance;
    ok = ep.pdf > 0 && std::isfinite(ep.pdf);
  } else {
    ok = lights.sample_point_on(en.emitter, en.pmf, u_point, ep, &sampled.env_radiance);
  }
  sampled.pdf = ep.pdf;
  return ok;
}

struct NeeSample {
  EmitterPoint ep;
  Terminal t;
  float mis = 0;
  float density = 0;  // light_pdf for one candidate; 1 / W for several
};
RESTIR_HD inline bool nee_light(const PathWorld& world, const PathSettings& ps, const Vertex& v, uint64_t seed, int vertex,
                                const VertexRandoms& u, const LightTileView& tile, NeeSample& out) {
  const int n = ps.pt.nee_candidates;
  if (n <= 1) {
    SampledEmitter sampled;
    if (!world.lights.sample_point(u.nee_select, u.nee_point, out.ep, &sampled.env_radiance)) return false;
    sampled.pdf = out.ep.pdf;
    out.t = eval_terminal(world, ps, v, out.ep.emitter, out.ep.position, out.ep.normal, &sampled);
    out.mis = strategy_weight(ps, true, v.delta, out.t.light_pdf, out.t.bsdf_pdf);
    out.density = out.t.light_pdf;
    return true;
  }
  Pcg32 r(mix64(seed ^ (0xd1b54a32d192ed03ULL * uint64_t(vertex + 1))), uint64_t(vertex) * 2 + 2);
  float w_sum = 0, q_chosen = 0;
  for (int i = 0; i < n; ++i) {
    const float u_select = i == 0 ? u.nee_select : r.next_float();
    const Vec2 u_point = i == 0 ? u.nee_point : r.next_2d();
    const float u_keep = r.next_float();
    EmitterPoint ep;
    SampledEmitter sampled;
    if (!nee_candidate(world.lights, tile, u_select, u_point, ep, sampled)) continue;
    const Terminal t = eval_terminal(world, ps, v, ep.emitter, ep.position, ep.normal, &sampled);
    const float mis = strategy_weight(ps, true, v.delta, t.light_pdf, t.bsdf_pdf);
    const float q = luminance(t.fcos * t.emission) * t.geometry * mis;
    const float w = q / (float(n) * ep.pdf);
    if (!(w > 0) || !std::isfinite(w)) continue;
    w_sum += w;
    if (u_keep * w_sum < w) out = NeeSample{ep, t, mis, 0}, q_chosen = q;
  }
  if (!(w_sum > 0)) return false;
  // Tests only (PathSettings::nee_source_density): the chosen point weighted by its source density.
  out.density = ps.nee_source_density ? out.t.light_pdf : q_chosen / w_sum;
  return true;
}

// One direction-sampling step from v with the vertex's random numbers: sample, trace, and express
// the segment by the vertex positions, so that a path's value depends on its vertices only (a shift
// that reconnects to a vertex recomputes exactly the same terms as the walk that found it).
struct Step {
  bool ok = false;
  bool hit = false;  // false: escaped (direction only)
  bool delta = false;
  Vec3 dir;       // unit direction of the segment
  Rgb fcos{0};    // f_s(v) |cos| for dir
  float pdf = 0;  // density of sample_direction at v for dir (solid angle)
  float distance = 0;
  SurfaceInteraction si;
};

template <class Tracer>
RESTIR_HD Step take_step(const PathWorld& world, const Tracer& tracer, const PathSettings& ps, const Vertex& v,
                         const VertexRandoms& u) {
  Step st;
  BsdfSample bs;
  const Vec3 wo_l = v.frame.to_local(v.wo);
  if (!sample_direction(v.bsdf, ps.path.bsdf_sampling, wo_l, u.lobe, u.direction, bs) || !(bs.pdf > 0) || is_black(bs.f)) return st;
  const Vec3 wi = v.frame.to_world(bs.wi);
  st.delta = bs.is_delta;
  st.dir = wi;
  st.fcos = bs.f * std::fabs(bs.wi.z);
  st.pdf = bs.pdf;
  Hit hit;
  const Ray ray = spawn_ray(v.p, v.ng, wi, world.ray_epsilon);
  st.ok = true;
  if (!tracer.intersect(ray, hit)) return st;
  st.hit = true;
  st.si = surface_interaction(world.scene, ray, hit);
  const Vec3 d = st.si.p - v.p;
  st.distance = length(d);
  if (!(st.distance > 0)) return Step{};
  if (!bs.is_delta) {
    st.dir = d / st.distance;
    const Vec3 dl = v.frame.to_local(st.dir);
    st.fcos = bsdf_eval(v.bsdf, wo_l, dl) * std::fabs(dl.z);
    st.pdf = direction_pdf(v.bsdf, ps.path.bsdf_sampling, wo_l, dl);
    if (!(st.pdf > 0) || is_black(st.fcos)) return Step{};
  }
  return st;
}

// x_k as a path's description needs it (describe_path): x_{k-1}'s position, the density of the
// replayed directions before x_{k-1}, x_k's point, normals, material and reflectance, and ω_k.
struct RcVertex {
  Vec3 previous;
  float replay = 1;
  Vec3 p, ng, shading_normal;
  int material = -1;
  Rgb reflectance{0};
  Vec3 out;
};
RESTIR_HD inline RcVertex rc_vertex(const Vertex& prev, float replay, const Vertex& xk, Vec3 out) {
  return {prev.p, replay, xk.p, xk.ng, xk.frame.n, xk.material, xk.bsdf.reflectance, out};
}

// The walk's bookkeeping at step d (vertex x_d), constant in size whatever the path length (issue
// 48: on the GPU a thread's state lives in registers, not in 66 stored vertices): the two vertices
// the criterion looks at, left-folded products of the walk's terms, and the reconnection vertex
// that every longer path shares. The hybrid criterion (GRIS §7.2) takes the *first* reconnectable
// pair (x_{k-1}, x_k); a pair with k <= n - 2 reads only the walk's own continuation at x_k, so it
// is decided as soon as that continuation is sampled, once for all longer paths (`found`); a path
// offered at x_d tests only its own last pair (x_{d-1}, x_d) and its emitter (reconnection_index).
// The products are formed in the order the stored walk formed them, so every float is the same.
struct Walk {
  Vertex prev, cur;             // x_{d-1} (d >= 2), x_d
  Vec3 prev_out;                // the direction of the step x_{d-1} -> x_d
  bool prev_delta_out = false;  // that step went through a delta lobe
  bool v1_delta = false, delta_out1 = false, delta_out2 = false;  // pt.shift = reconnection's test
  Rgb prefix{1};                // Π_{i<d} f_s|cos| of the continuations
  float replay_prev = 1;        // Π_{i<=d-2} of the continuations' stored densities
  float replay_cur = 1;         // Π_{i<=d-1}
  int found = 0;                // the reconnection vertex of every path longer than found + 1 (0: none yet)
  RcVertex rc;                  // x_found
  Rgb between{1};               // Π_{found<i<d} f_s|cos|
  float footprint = 0;          // footprint_threshold of the walk's primary hit x_1
};

// Reconnection vertex k of the path offered at step d, ending in an emitter at x_n, n = d + 1
// (hybrid: the first reconnectable pair; reconnection: 2; random replay: 0). Reconnection needs a
// non-delta x_1 and non-delta events at x_1 and x_2 (a delta cannot connect to an arbitrary x_2,
// nor keep x_2's outgoing direction for another incoming one): such paths get k = 0 and no
// reconnection shift, in either direction. `last_delta`: the event at x_{n-1} (false for NEE);
// `last_out` its direction (toward x_n).
RESTIR_HD inline int reconnection_index(const PathSettings& ps, const Walk& w, int d, Vec3 terminal_pos, Vec3 terminal_normal,
                                        bool terminal_is_direction, bool last_delta, Vec3 last_out, bool nee) {
  const int n = d + 1;
  if (ps.pt.shift == ShiftMapping::random_replay) return 0;
  if (ps.pt.shift == ShiftMapping::reconnection) {
    const bool event1 = d == 1 ? last_delta : w.delta_out1;
    const bool event2 = n > 2 && (d == 2 ? last_delta : w.delta_out2);
    return w.v1_delta || event1 || event2 ? 0 : 2;
  }
  if (w.found > 0) return w.found;
  if (d >= 2 && !w.prev.delta && !w.prev_delta_out && !last_delta) {  // (x_{n-2}, x_{n-1}) with x_{n-1}'s event toward x_n
    const float distance = length(w.cur.p - w.prev.p);
    if (pair_opens(ps, w.prev, w.cur, w.prev_out, distance, w.footprint) &&
        pair_completes(ps, w.cur, w.prev.ng, w.prev_out, distance, last_out, w.footprint))
      return d;
  }
  // Emitters are diffuse or delta: always reconnectable; lights at infinity are infinitely far.
  if (w.cur.delta || last_delta) return 0;
  const float distance = terminal_is_direction ? 0.0f : length(terminal_pos - w.cur.p);
  return emitter_reconnectable(ps, w.cur, terminal_is_direction, terminal_normal, last_out, distance, w.footprint, nee) ? n : 0;
}

// After the continuation from x_d (direction `out`, `delta` its event): the pair (x_{d-1}, x_d) is
// decided for every longer path. Hybrid: found = d if it is the first reconnectable one.
// Reconnection: x_2 is kept (reconnection_index decides from the deltas).
RESTIR_HD inline void decide_pair(const PathSettings& ps, Walk& w, int d, Vec3 out, bool delta) {
  if (d == 1) w.delta_out1 = delta;
  if (d == 2) w.delta_out2 = delta;
  if (w.found > 0 || d < 2 || ps.pt.shift == ShiftMapping::random_replay) return;
  if (ps.pt.shift == ShiftMapping::hybrid) {
    if (w.prev.delta || w.prev_delta_out || delta) return;
    const float distance = length(w.cur.p - w.prev.p);
    if (!pair_opens(ps, w.prev, w.cur, w.prev_out, distance, w.footprint) ||
        !pair_completes(ps, w.cur, w.prev.ng, w.prev_out, distance, out, w.footprint))
      return;
  }
  w.found = d;
  w.rc = rc_vertex(w.prev, w.replay_prev, w.cur, out);
  w.between = Rgb(1);
}

// Fills the reconnection / replay description of the path offered at step d = n - 1 (s.nee set).
// `last_fcos` is the f_s|cos| of the final segment, `tail` = Le G, `replay_pdf` the path density a
// shift's replay sees (own measure; the roulette's only under pt.roulette = replayed), `mis` its
// strategy weight, `t` the terminal (for k = n - 1).
RESTIR_HD inline void describe_path(const PathSettings& ps, const Walk& w, int n, uint32_t emitter, Vec3 pos, Vec3 normal,
                                    bool is_direction, bool last_delta, Rgb last_fcos, Rgb tail, float replay_pdf, float mis,
                                    const Terminal& t, PathSample& s) {
  const int d = n - 1;
  s.length = uint8_t(n);
  const int k = reconnection_index(ps, w, d, pos, normal, is_direction, last_delta, t.wi, s.nee);
  s.rc = uint8_t(k);
  if (k == 0) {
    s.replay_pdf = replay_pdf;
    return;
  }
  if (k == n) {
    s.rc_previous = w.cur.p;
    s.replay_pdf = w.replay_cur;
    s.rc_position = pos;
    s.rc_normal = normal;
    s.rc_emitter = emitter;
    // Kept for the environment, whose radiance and density depend on x_n's direction alone, so
    // that a reconnection shift need not look them up again (shift_path).
    s.rc_suffix = tail;
    s.rc_tail_light_pdf = t.light_pdf;
    return;
  }
  const RcVertex xk = k == w.found ? w.rc : rc_vertex(w.prev, w.replay_prev, w.cur, t.wi);
  s.rc_previous = xk.previous;
  s.replay_pdf = xk.replay;
  s.rc_position = xk.p;
  s.rc_normal = xk.ng;
  s.rc_material = xk.material;
  s.rc_reflectance = xk.reflectance;
  s.rc_shading_normal = xk.shading_normal;
  s.rc_out = xk.out;
  // Le G × (Π_{k<i<n-1} f_s|cos|, folded from the left) × the last segment's.
  s.rc_suffix = tail * (k < d ? w.between : Rgb(1)) * (k < d ? last_fcos : Rgb(1));
  if (k < n - 1) {
    s.rc_mis = mis;
  } else {
    s.rc_tail_light_pdf = t.light_pdf;
    s.rc_tail_measure = t.measure;
  }
}

// One path of a walk as the walk offers it: x_1..x_n ending at an emitter point.
struct OfferedPath {
  int n;
  bool nee_tag;
  uint32_t emitter;
  Vec3 pos, normal;
  bool is_direction;
  bool last_delta;      // the final segment went through a delta lobe (never for NEE)
  Rgb last_fcos, tail;  // f_s|cos| of the final segment; Le G
  float path_pdf, mis;  // full path density (own measure, Russian roulette included); m_t
  float replay_pdf;     // the same without roulette under pt.roulette = initial (what shifts replay)
  const Terminal* terminal;
};

// Russian roulette after the step that reached vertex `next` (deciding whether the walk goes on
// from it). Returns the survival probability (0 = terminated).
//  - pt.roulette = replayed: part of the primary sample space, replayed by every shift. The survival
//    probability is the next vertex's albedo, a property of that vertex alone: a reconnection shift
//    keeps x_k and everything after it, so the suffix's decisions (same random numbers, same
//    probabilities) are identical in the base and the offset path and cancel, while the replayed
//    prefix's probabilities enter its pdf and hence the Jacobian (GRIS §6.1: the map is the
//    identity in primary sample space, including the roulette numbers). A throughput-based
//    probability would change along a reconnected suffix and make the shift non-invertible.
//  - pt.roulette = initial (ReSTIR PT Enhanced, Lin, Kettunen, Wyman 2026, sec. 6.2.4; supplement
//    §6): the primary sample space has no roulette dimensions; roulette only decides which paths
//    the initial walk offers, so a path of n vertices is a candidate with density p(x̄) Π q_i, the
//    q_i any function of the path's own prefix (here pbrt-v4's: max component of the throughput
//    `beta`, roulette divided out as in path_pixel.h). The initial RIS weight divides by it; the
//    shifts replay without roulette and their Jacobians are ratios of roulette-free densities.
RESTIR_HD inline float roulette(const PathSettings& ps, int d, const Vertex& next, const VertexRandoms& u, Rgb beta) {
  if (!ps.path.russian_roulette || d < ps.path.rr_min_depth) return 1.0f;
  const float m = max_component(beta);
  const float q = ps.pt.roulette == Roulette::initial ? (m < 1 ? m : 1.0f) : roulette_survival(next.bsdf);
  return u.roulette < q ? q : 0.0f;
}
// The roulette a shift replays at the same step (none under pt.roulette = initial).
RESTIR_HD inline float replayed_roulette(const PathSettings& ps, int d, const Vertex& next, const VertexRandoms& u) {
  return ps.pt.roulette == Roulette::replayed ? roulette(ps, d, next, u, Rgb(1)) : 1.0f;
}

// One walk from the primary surface s with the random streams of walk_seed; calls
// offer(const OfferedPath&) for every path it contains (each NEE connection and each emitter hit).
// `tile`: the pixel's light tile, read by resampled NEE only (pt.nee_candidates > 1).
template <class Tracer, class Offer>
RESTIR_HD void walk_from(const PathWorld& world, const Tracer& tracer, const PathSettings& ps, const GSurface& s,
                         uint64_t walk_seed, Walk& w, const Offer& offer, const LightTileView& tile = {}) {
  const int max_depth = ps.path.max_depth < kMaxVertices - 2 ? ps.path.max_depth : kMaxVertices - 2;  // by value (device code)
  w.cur = vertex_from_surface(s);
  w.prev_delta_out = false;
  w.v1_delta = w.cur.delta;
  w.delta_out1 = w.delta_out2 = false;
  w.prefix = Rgb(1);
  w.replay_prev = w.replay_cur = 1;
  w.found = 0;
  w.between = Rgb(1);
  w.footprint = footprint_threshold(ps, s);
  float pdf = 1;     // density of the walk's prefix, roulette included (the initial RIS weights')
  float replay = 1;  // the same as a shift replays it (roulette only under pt.roulette = replayed)
  Rgb beta(1);       // throughput, roulette divided out (pt.roulette = initial's survival)
  for (int d = 1; d <= max_depth; ++d) {
    const Vertex& v = w.cur;
    const VertexRandoms u = vertex_randoms(walk_seed, d);
    // Next-event estimation: path x_1..x_d + light point.
    NeeSample nee;
    if (ps.path.nee && !v.delta && nee_light(world, ps, v, walk_seed, d, u, tile, nee)) {
      const Terminal& t = nee.t;
      const EmitterPoint& ep = nee.ep;
      if (!is_black(t.fcos * t.emission) && !tracer.occluded(t.shadow))
        offer(OfferedPath{d + 1, true, ep.emitter, ep.position, ep.normal, world.lights.at_infinity(ep.emitter), false, t.fcos,
                          t.emission * t.geometry, pdf * nee.density, nee.mis, replay * nee.density, &t});
    }
    // Continue by direction sampling; an emitter hit is the BSDF strategy's path x_1..x_{d+1}.
    const Step st = take_step(world, tracer, ps, v, u);
    if (!st.ok) break;
    decide_pair(ps, w, d, st.dir, st.delta);
    if (!st.hit) {
      if (world.lights.has_environment()) {
        const uint32_t e = world.lights.environment_emitter();
        const LightsView::EnvironmentValue env = world.lights.environment_value(st.dir);
        Terminal t;
        t.wi = st.dir;
        t.light_pdf = env.pdf;
        t.measure = 1;
        t.bsdf_pdf = st.delta ? 0.0f : st.pdf;
        const float mis = strategy_weight(ps, false, v.delta || st.delta, t.light_pdf, t.bsdf_pdf);
        offer(OfferedPath{d + 1, false, e, st.dir, Vec3(0), true, st.delta, st.fcos, env.radiance, pdf * st.pdf, mis, replay * st.pdf, &t});
      }
      break;
    }
    const SurfaceInteraction& si = st.si;
    const uint32_t e = emitter_of(world, si);
    if (e != kNoEmitter) {
      const Rgb le = world.lights.emitted(e, si.ng, -st.dir);
      if (!is_black(le)) {
        Terminal t;
        t.wi = st.dir;
        t.measure = std::fabs(dot(si.ng, st.dir)) / (st.distance * st.distance);
        t.light_pdf = world.lights.point_pdf(e, si.p);
        t.bsdf_pdf = st.delta ? 0.0f : st.pdf * t.measure;
        const float mis = strategy_weight(ps, false, v.delta || st.delta, t.light_pdf, t.bsdf_pdf);
        offer(OfferedPath{d + 1, false, e, si.p, si.ng, false, st.delta, st.fcos, le * t.measure, pdf * st.pdf * t.measure, mis,
                          replay * st.pdf * t.measure, &t});
      }
    }
    if (d == max_depth) break;
    const Vertex next = vertex_from_hit(world, si, -st.dir);
    beta *= st.fcos / st.pdf;
    const float q = roulette(ps, d, next, u, beta);
    if (!(q > 0)) break;
    beta /= q;
    // The survival probability is part of the continuation's density. Replayed roulette: every
    // stored pdf (the replayed prefix's included) carries it, as the shifted paths' do. Initial
    // roulette: only the candidate's density `pdf` does (a planted bias of the tests,
    // PathSettings::roulette_in_replay, leaves it in the stored ones too).
    const bool stored = ps.pt.roulette == Roulette::replayed || ps.roulette_in_replay;
    pdf *= st.pdf * q;
    replay *= stored ? st.pdf * q : st.pdf;
    // Step d + 1: x_{d+1} becomes the current vertex.
    if (w.found > 0 && d > w.found) w.between *= st.fcos;
    w.prefix *= st.fcos;
    w.replay_prev = w.replay_cur;
    w.replay_cur = replay;
    w.prev = w.cur;
    w.cur = next;
    w.prev_out = st.dir;
    w.prev_delta_out = st.delta;
  }
}

// The contribution m_t f of an offered path; beta of a path is the product of the walk's f_s|cos|
// before its last segment.
RESTIR_HD inline Rgb offered_contribution(const Walk& w, const OfferedPath& o) {
  return w.prefix * o.last_fcos * o.tail * o.mis;
}

RESTIR_HD inline PathSample describe_offered(const PathSettings& ps, const Walk& w, const OfferedPath& o, uint64_t walk_seed) {
  PathSample x;
  x.seed = walk_seed;
  x.nee = o.nee_tag;
  x.contribution = offered_contribution(w, o);
  describe_path(ps, w, o.n, o.emitter, o.pos, o.normal, o.is_direction, o.last_delta, o.last_fcos, o.tail, o.replay_pdf, o.mis,
                *o.terminal, x);
  return x;
}

}  // namespace pt_detail

// The seed of pixel p's initial paths in a frame's chain (spp sample): the CPU's stage and the
// device's stage alike.
RESTIR_HD inline uint64_t initial_paths_seed(uint64_t seed, uint32_t p, uint32_t frame, uint32_t chain) {
  return hash_combine(hash_combine(hash_combine(seed, p), frame), chain);
}

template <class Tracer>
RESTIR_HD PathReservoir initial_path_reservoir(const PathWorld& world, const Tracer& tracer, const PathSettings& ps,
                                                  const GSurface& s, uint64_t seed, int candidates, const LightTileView& tile = {}) {
  PathReservoir r;
  r.confidence = float(candidates);
  if (!s.valid || world.lights.empty()) return r;
  Pcg32 stream_rng(mix64(seed ^ 0x5bd1e995ULL), 7);
  pt_detail::Walk w;
  for (int c = 0; c < candidates; ++c) {
    const uint64_t walk_seed = hash_combine(seed, uint64_t(c));
    pt_detail::walk_from(world, tracer, ps, s, walk_seed, w, [&](const pt_detail::OfferedPath& o) {
      const Rgb contribution = pt_detail::offered_contribution(w, o);
      const float target = o.n >= ps.min_length ? luminance(contribution) : 0.0f;
      if (!(o.path_pdf > 0) || target == 0) {
        (void)stream_rng.next_float();
        return;
      }
      if (restir::stream(r, PathSample{}, target, target / o.path_pdf / float(candidates), stream_rng.next_float()))
        r.sample = pt_detail::describe_offered(ps, w, o, walk_seed);
    }, tile);
  }
  restir::finalize(r);
  return r;
}

}  // namespace rl
