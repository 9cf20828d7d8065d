// ReSTIR PT's walks (pt_path.h documents the paths; path_terms.h the terms): next-event
// estimation (one light sample or resampled candidates), one direction-sampling step, a walk from
// the primary hit with every path it offers (NEE connections and emitter hits, each MIS-weighted by
// its strategy), the reconnection vertex a walk chooses, and the initial resampling over them.
// RESTIR_HD over a PathWorld and a Tracer (frame_world.h): every backend runs this one
// implementation of every path density and MIS weight; the shifts (shift_*.h) replay and reconnect
// the same pieces.
#pragma once
#include "frame/light_tiles.h"
#include "integrators/restir_pt/path_terms.h"
#include "restir/shift.h"

namespace rl {

namespace pt_detail {

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
// replayed directions before x_{k-1}, x_k's point, geometric normal and what identifies its
// surface (surface_at), and ω_k.
struct RcVertex {
  Vec3 previous;
  float replay = 1;
  Vec3 p, ng;
  uint32_t geom = kInvalidId, prim = 0;
  Vec2 barycentrics;
  Vec3 out;
};
RESTIR_HD inline RcVertex rc_vertex(const Vertex& prev, float replay, const Vertex& xk, Vec3 out) {
  return {prev.p, replay, xk.p, xk.ng, xk.geom, xk.prim, xk.barycentrics, out};
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
  s.rc_geometry = restir::reconnection_geometry(xk.previous, xk.p, xk.ng);
  s.replay_pdf = xk.replay;
  s.rc_position = xk.p;
  s.rc_geom = xk.geom;
  s.rc_prim = xk.prim;
  s.rc_barycentrics = xk.barycentrics;
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

// The BSDF strategy's path x_1..x_{d+1} when the step st from x_d = v escaped to the environment or
// hit an emitter: offered with the walk's prefix densities `pdf` and `replay` (walk_from).
template <class Offer>
RESTIR_HD void offer_emitter_hit(const PathWorld& world, const PathSettings& ps, const Vertex& v, const Step& st, int d, float pdf,
                                 float replay, const Offer& offer) {
  Terminal t;
  t.wi = st.dir;
  if (!st.hit) {
    if (!world.lights.has_environment()) return;
    const uint32_t e = world.lights.environment_emitter();
    const LightsView::EnvironmentValue env = world.lights.environment_value(st.dir);
    t.light_pdf = env.pdf;
    t.measure = 1;
    t.bsdf_pdf = st.delta ? 0.0f : st.pdf;
    const float mis = strategy_weight(ps, false, v.delta || st.delta, t.light_pdf, t.bsdf_pdf);
    offer(OfferedPath{d + 1, false, e, st.dir, Vec3(0), true, st.delta, st.fcos, env.radiance, pdf * st.pdf, mis, replay * st.pdf, &t});
    return;
  }
  const SurfaceInteraction& si = st.si;
  const uint32_t e = emitter_of(world, si);
  if (e == kNoEmitter) return;
  const Rgb le = world.lights.emitted(e, si.ng, -st.dir);
  if (is_black(le)) return;
  t.measure = std::fabs(dot(si.ng, st.dir)) / (st.distance * st.distance);
  t.light_pdf = world.lights.point_pdf(e, si.p);
  t.bsdf_pdf = st.delta ? 0.0f : st.pdf * t.measure;
  const float mis = strategy_weight(ps, false, v.delta || st.delta, t.light_pdf, t.bsdf_pdf);
  offer(OfferedPath{d + 1, false, e, si.p, si.ng, false, st.delta, st.fcos, le * t.measure, pdf * st.pdf * t.measure, mis,
                    replay * st.pdf * t.measure, &t});
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
    offer_emitter_hit(world, ps, v, st, d, pdf, replay, offer);
    if (!st.hit || d == max_depth) break;
    const Vertex next = vertex_from_hit(world, st.si, -st.dir);
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
