// Random replay (GRIS, Lin et al. 2022, §6.1): the offset path re-traces the base path's random
// numbers from the other pixel's primary hit, vertex by vertex (walk.h's per-vertex streams). The
// map is the identity in primary sample space, so |∂ȳ/∂x̄| = p(x̄) / p(ȳ), each density the whole
// path's in its own measure (Russian roulette's survival probabilities included). The hybrid shift
// (shift_hybrid.h) replays its prefix with the same two functions.
#pragma once
#include "integrators/restir_pt/walk.h"

namespace rl {

namespace pt_detail {

// The offset path so far: its vertex y_d, the product of its f_s|cos| before y_d, and the density
// of its replayed directions. `pending`: the pair (y_{d-1}, y_d) passes the hybrid criterion in all
// but y_d's own event, which the next step (or the reconnection, or the last segment) decides
// (pending_completes); the pair's y_{d-1} normal, direction and length are kept for that.
// `footprint`: footprint_threshold of the offset path's own primary hit y_1 (the criterion is
// evaluated in the offset path's domain, as its own walk would: Lin et al. 2026, supplement §2).
struct ShiftPrefix {
  Vertex v;
  Rgb beta{1};
  float pdf = 1;
  bool pending = false;
  float footprint = 0;
  Vec3 pending_ng{0}, pending_dir{0};
  float pending_distance = 0;
};

// The pending pair (y_{d-1}, y_d = pre.v) given y_d's non-delta event toward b_out: reconnectable?
RESTIR_HD inline bool pending_completes(const PathSettings& ps, const ShiftPrefix& pre, Vec3 b_out) {
  return pre.pending && pair_completes(ps, pre.v, pre.pending_ng, pre.pending_dir, pre.pending_distance, b_out, pre.footprint);
}

// Replays the base path's directions at y_1 .. y_{last-1} with its random numbers, from pre.v = y_1
// to pre.v = y_last. `check`: the hybrid shift's invertibility test (GRIS §7.2, eqs. 19-20): the
// offset path must get the same reconnection index from its own walk as the base path, or the
// inverse shift (and with it the MIS weights' partition of unity) differs, so no replayed vertex
// pair before x_k may be reconnectable (walk.h: pair_opens / pair_completes, non-delta events). A
// pair's second event (and, under the footprint criterion, its inverse footprint) is known one step
// later; with a BSDF that has no delta lobe and no inverse footprint test the pair is reconnectable
// for sure and fails at once. The last pair stays in pre.pending for the caller.
template <class Tracer>
RESTIR_HD bool replay_prefix(const PathWorld& world, const Tracer& tracer, const PathSettings& ps, const PathSample& base, int last,
                             bool check, ShiftPrefix& pre) {
  for (int d = 1; d < last; ++d) {
    const VertexRandoms u = vertex_randoms(base.seed, d);
    const Step st = take_step(world, tracer, ps, pre.v, u);
    if (!st.ok || !st.hit) return false;
    if (check && !st.delta && pending_completes(ps, pre, st.dir)) return false;  // (y_{d-1}, y_d) was reconnectable
    const Vertex next = vertex_from_hit(world, st.si, -st.dir);
    pre.pending = check && !st.delta && !pre.v.delta && pair_opens(ps, pre.v, next, st.dir, st.distance, pre.footprint);
    if (pre.pending && !bsdf_has_delta(next.bsdf) && !inverse_tested(ps, next)) return false;
    pre.pending_ng = pre.v.ng;
    pre.pending_dir = st.dir;
    pre.pending_distance = st.distance;
    pre.beta *= st.fcos;
    // The roulette decision that let the base path reach its vertex d + 1, replayed (see roulette();
    // none under pt.roulette = initial).
    const float q = replayed_roulette(ps, d, next, u);
    if (!(q > 0)) return false;
    pre.pdf *= st.pdf * q;
    pre.v = next;
  }
  return true;
}

// A shift's result: out takes the offset path's contribution m_t f and the density of its replayed
// part; true when the shift succeeded (a contribution and a finite, positive Jacobian).
RESTIR_HD inline bool shifted(Rgb contribution, float replay_pdf, float jacobian_value, PathSample& out, float& jacobian) {
  out.contribution = contribution;
  out.replay_pdf = replay_pdf;
  jacobian = jacobian_value;
  return !is_black(out.contribution) && std::isfinite(jacobian) && jacobian > 0;
}

// The offset path's last segment, drawn by one of the two strategies.
struct ReplayedTail {
  Rgb f;       // the path's f
  float p;     // its density
  float mis;   // m_t of its strategy
};

// The last vertex by next-event estimation from y_{n-1} = pre.v, with the base path's numbers u.
// Never under pt.nee_candidates > 1, whose resampled light choice has no density to replay with
// (walk.h, nee_light; restir_pt.cpp refuses the settings that would replay it): the shift fails.
template <class Tracer>
RESTIR_HD bool replay_nee(const PathWorld& world, const Tracer& tracer, const PathSettings& ps, const VertexRandoms& u, bool check,
                          const ShiftPrefix& pre, ReplayedTail& tail) {
  const Vertex& v = pre.v;
  EmitterPoint ep;
  SampledEmitter sampled;
  if (v.delta || !ps.path.nee || ps.pt.nee_candidates > 1 ||
      !world.lights.sample_point(u.nee_select, u.nee_point, ep, &sampled.env_radiance))
    return false;
  const bool is_dir = world.lights.at_infinity(ep.emitter);
  // NEE's event is never a delta: it completes a pending pair, and (y_{n-1}, x_n) is one to test.
  sampled.pdf = ep.pdf;
  const Terminal t = eval_terminal(world, ps, v, ep.emitter, ep.position, ep.normal, &sampled);
  if (check && (pending_completes(ps, pre, t.wi) ||
                emitter_reconnectable(ps, v, is_dir, ep.normal, t.wi, is_dir ? 0.0f : length(ep.position - v.p), pre.footprint,
                                      ps.retest_forced_nee)))
    return false;
  if (is_black(t.fcos * t.emission) || tracer.occluded(t.shadow)) return false;
  tail.f = pre.beta * t.fcos * t.emission * t.geometry;
  tail.p = pre.pdf * t.light_pdf;
  tail.mis = strategy_weight(ps, true, v.delta, t.light_pdf, t.bsdf_pdf);
  return true;
}

// The last vertex by direction sampling from y_{n-1} = pre.v: an emitter or the environment hit.
template <class Tracer>
RESTIR_HD bool replay_bsdf(const PathWorld& world, const Tracer& tracer, const PathSettings& ps, const VertexRandoms& u, bool check,
                           const ShiftPrefix& pre, ReplayedTail& tail) {
  const Vertex& v = pre.v;
  const Step st = take_step(world, tracer, ps, v, u);
  if (!st.ok) return false;
  if (check && !st.delta &&
      (pending_completes(ps, pre, st.dir) ||
       emitter_reconnectable(ps, v, !st.hit, st.hit ? st.si.ng : Vec3(0), st.dir, st.distance, pre.footprint, false)))
    return false;
  float light_pdf, measure;
  Rgb le;
  if (!st.hit) {
    if (!world.lights.has_environment()) return false;
    const LightsView::EnvironmentValue env = world.lights.environment_value(st.dir);
    le = env.radiance;
    light_pdf = env.pdf;
    measure = 1;
  } else {
    const uint32_t e = emitter_of(world, st.si);
    if (e == kNoEmitter) return false;
    le = world.lights.emitted(e, st.si.ng, -st.dir);
    measure = std::fabs(dot(st.si.ng, st.dir)) / (st.distance * st.distance);
    light_pdf = world.lights.point_pdf(e, st.si.p);
  }
  tail.f = pre.beta * st.fcos * le * measure;
  tail.p = pre.pdf * st.pdf * measure;
  tail.mis = strategy_weight(ps, false, v.delta || st.delta, light_pdf, st.delta ? 0.0f : st.pdf * measure);
  return true;
}

// A path without reconnection vertex (k = 0): its last vertex by the base path's strategy, with its
// random numbers, from y_{n-1} = pre.v (vertex `last` = n - 1); out (a copy of base) takes the
// offset path's contribution and density, jacobian = p(x̄) / p(ȳ).
template <class Tracer>
RESTIR_HD bool replay_last_vertex(const PathWorld& world, const Tracer& tracer, const PathSettings& ps, const PathSample& base, int last,
                                  bool check, const ShiftPrefix& pre, PathSample& out, float& jacobian) {
  const VertexRandoms u = vertex_randoms(base.seed, last);
  ReplayedTail tail;
  if (!(base.nee ? replay_nee(world, tracer, ps, u, check, pre, tail) : replay_bsdf(world, tracer, ps, u, check, pre, tail)))
    return false;
  return shifted(tail.f * tail.mis, tail.p, tail.p > 0 ? base.replay_pdf / tail.p : 0.0f, out, jacobian);
}

}  // namespace pt_detail

// The random-replay shift of `base` to the pixel whose primary surface is y1 (a valid surface).
// Its walks choose no reconnection vertex (reconnection_index), so every sample replays whole.
template <class Tracer>
RESTIR_HD bool shift_random_replay(const PathWorld& world, const Tracer& tracer, const PathSettings& ps, const PathSample& base,
                                   const GSurface& y1, PathSample& out, float& jacobian) {
  using namespace pt_detail;
  if (base.rc != 0) return false;
  ShiftPrefix pre{vertex_from_surface(y1)};
  const int last = base.length - 1;
  if (!replay_prefix(world, tracer, ps, base, last, false, pre)) return false;
  out = base;
  return replay_last_vertex(world, tracer, ps, base, last, false, pre, out, jacobian);
}

}  // namespace rl
