// Reconnection (ReSTIR GI, Ouyang et al. 2021; GRIS, Lin et al. 2022, §6.2): the offset path keeps
// the base path's reconnection vertex x_k and everything after it, and connects its own y_{k-1}
// to x_k. The Jacobian of the map (solid angle at x_{k-1} -> at y_{k-1}, x_k fixed; ReSTIR GI
// eq. 11) is |cos θ_k^y| / |cos θ_k^x| · |x_k − x_{k−1}|² / |x_k − y_{k−1}|², and 1 when x_k is the
// emitter vertex (area measure); a replayed prefix before y_{k-1} (the hybrid shift) adds its pdf
// ratio. shift_reconnection itself reconnects at k = 2, the primary hit's successor.
#pragma once
#include "integrators/restir_pt/shift_random_replay.h"
#include "restir/shift.h"

namespace rl {

namespace pt_detail {

// The offset path's value at its reconnection: f up to the emitter and m_t of the base path's
// strategy there, and the reconnection's Jacobian.
struct Reconnected {
  Rgb f;
  float mis;
  float jacobian = 1;
  float geometry = 0;  // x_k a surface: the offset path's half of the Jacobian (its rc_geometry)
};

// x_k is the emitter vertex x_n: y_{n-1} = pre.v connects to the base path's light point.
template <class Tracer>
RESTIR_HD bool reconnect_emitter(const PathWorld& world, const Tracer& tracer, const PathSettings& ps, const PathSample& base,
                                 const ShiftPrefix& pre, Reconnected& r) {
  const Vertex& v = pre.v;
  const bool is_dir = world.lights.at_infinity(base.rc_emitter);
  // x_n's direction is the base path's, so the environment's radiance (Le G, G = 1) and density
  // there are the base path's too -- the same bits the lookup would give -- as long as the
  // lights are those that made the sample (always, unless the lights are animated). The lookup's
  // cache misses in the texel table were ~5% of a ReSTIR PT frame on the env-lit teapots (perf).
  // (A distant light's L and pmf are the same for every receiver as well; eval_terminal reads them
  // from the emitter, using only the kept density.)
  const SampledEmitter kept{base.rc_tail_light_pdf, base.rc_suffix};
  const bool reuse = is_dir && world.lights.fixed;
  const Terminal t = eval_terminal(world, ps, v, base.rc_emitter, base.rc_position, base.rc_normal, reuse ? &kept : nullptr);
  if (is_black(t.fcos * t.emission) || tracer.occluded(t.shadow)) return false;
  r.f = pre.beta * t.fcos * t.emission * t.geometry;
  r.mis = strategy_weight(ps, base.nee, v.delta, t.light_pdf, t.bsdf_pdf);
  return true;
}

// The direction from y_{k-1} = v toward x_k and its length, as the walk and eval_terminal compute
// them (d / sqrt(d²)), so that both sides of a shift see the same bits: x_k's direction itself and
// length 0 for an emitter at infinity. false where x_k is v's own point.
RESTIR_HD inline bool toward_rc(const PathWorld& world, const PathSample& base, const Vertex& v, Vec3& dir, float& distance) {
  distance = 0;
  dir = base.rc_position;
  if (base.rc == base.length && world.lights.at_infinity(base.rc_emitter)) return true;
  const Vec3 d = base.rc_position - v.p;
  const float d2 = length_squared(d);
  if (!(d2 > 0)) return false;
  distance = std::sqrt(d2);
  dir = d / distance;
  return true;
}

// x_k (k < n) as the offset path reaches it, arriving along `dir`: its surface rebuilt from what
// the sample keeps of it (surface_at: the same bits as the walk that found it). false where it
// cannot be (a degenerate triangle: every shift of such a path fails, in both directions alike).
RESTIR_HD inline bool rc_surface(const PathWorld& world, const PathSample& base, Vec3 dir, Vertex& xk) {
  SurfaceInteraction si;
  if (!surface_at(world.scene, base.rc_geom, base.rc_prim, base.rc_barycentrics, base.rc_position, si)) return false;
  xk = vertex_from_hit(world, si, -dir);
  return true;
}

// x_k is a surface vertex (k < n): y_{k-1} = pre.v connects to it (xk: rc_surface's), and the
// suffix after it is taken as it is.
template <class Tracer>
RESTIR_HD bool reconnect_surface(const PathWorld& world, const Tracer& tracer, const PathSettings& ps, const PathSample& base,
                                 const ShiftPrefix& pre, const Vertex& xk, Vec3 wi, Reconnected& r) {
  const Vertex& v = pre.v;
  if (tracer.occluded(spawn_ray_to(v.p, v.ng, xk.p, xk.ng, world.ray_epsilon))) return false;
  const Vec3 wo_l = v.frame.to_local(v.wo), wi_l = v.frame.to_local(wi);
  const Rgb fcos_v = bsdf_eval(v.bsdf, wo_l, wi_l) * std::fabs(wi_l.z);
  const Vec3 k_in = xk.frame.to_local(xk.wo), k_out = xk.frame.to_local(base.rc_out);
  const Rgb fcos_k = bsdf_eval(xk.bsdf, k_in, k_out) * std::fabs(k_out.z);
  r.f = pre.beta * fcos_v * fcos_k * base.rc_suffix;
  if (base.rc == base.length - 1) {  // x_k is the vertex before the emitter: its BSDF density enters m_t
    const float bsdf_pdf = direction_pdf(xk.bsdf, ps.path.bsdf_sampling, k_in, k_out) * base.rc_tail_measure;
    r.mis = strategy_weight(ps, base.nee, xk.delta, base.rc_tail_light_pdf, bsdf_pdf);
  } else {
    r.mis = base.rc_mis;
  }
  // Solid angle at x_{k-1} -> at y_{k-1} with x_k fixed (ReSTIR GI eq. 11; Lin et al. 2022 eq. 52):
  // the offset path's |cos φ_y| / |x_k − y_{k-1}|² over the base path's, which the sample keeps.
  r.geometry = restir::reconnection_geometry(v.p, xk.p, xk.ng);
  r.jacobian = restir::reconnection_jacobian_from(base.rc_geometry, r.geometry);
  return r.jacobian > 0;
}

// The hybrid shift's criterion on the offset path (GRIS §7.2; walk.h): the pair (y_{k-1}, x_k) must
// be reconnectable as (x_{k-1}, x_k) was -- under the footprint criterion with y_1's threshold and
// y_{k-1}'s own lobe density toward x_k, and x_k's inverse footprint for the new incoming direction
// (Lin et al. 2026, sec. 4, eq. 5) -- and the pending replayed pair (y_{k-2}, y_{k-1}) must not be,
// its event at y_{k-1} being the connection toward x_k: else the offset path's own walk would choose
// another k and the shift would not be invertible. dir, distance: toward_rc's. The part that reads
// x_k's surface (a direction-dependent criterion) is pair_reconnectable's, so that a shift the rest
// rejects does not rebuild x_k.
RESTIR_HD inline bool offset_reconnectable(const PathWorld& world, const PathSettings& ps, const PathSample& base, const ShiftPrefix& pre,
                                           Vec3 dir, float distance) {
  const Vertex& v = pre.v;
  if (pending_completes(ps, pre, dir)) return false;
  if (base.rc == base.length)
    return emitter_reconnectable(ps, v, world.lights.at_infinity(base.rc_emitter), base.rc_normal, dir, distance, pre.footprint,
                                 base.nee && ps.retest_forced_nee);
  // x_k's part of the criterion is its material's alone (roughness-distance): what x̄ passed.
  if (!criterion_depends_on_direction(ps)) return rough(v, ps.pt.roughness_threshold) && distance >= ps.pt.distance_threshold;
  return true;
}
// The rest of the criterion for a surface x_k (rc_surface's) under a direction-dependent criterion.
RESTIR_HD inline bool pair_reconnectable(const PathSettings& ps, const PathSample& base, const ShiftPrefix& pre, const Vertex& xk,
                                         Vec3 dir, float distance) {
  if (!criterion_depends_on_direction(ps)) return true;
  return pair_opens(ps, pre.v, xk, dir, distance, pre.footprint) && pair_completes(ps, xk, pre.v.ng, dir, distance, base.rc_out, pre.footprint);
}

// Reconnects y_{k-1} = pre.v to the base path's x_k; out (a copy of base) takes the offset path's
// contribution, replayed density and x_{k-1}; jacobian = p(replayed x̄) / p(replayed ȳ) times the
// reconnection's. `hybrid`: the offset path must pass the hybrid shift's criterion
// (offset_reconnectable), or the shift is not invertible.
template <class Tracer>
RESTIR_HD bool reconnect(const PathWorld& world, const Tracer& tracer, const PathSettings& ps, const PathSample& base, bool hybrid,
                         const ShiftPrefix& pre, PathSample& out, float& jacobian) {
  Vec3 dir;
  float distance;
  if (pre.v.delta || !toward_rc(world, base, pre.v, dir, distance)) return false;
  if (hybrid && !offset_reconnectable(world, ps, base, pre, dir, distance)) return false;
  Reconnected r;
  if (base.rc == base.length) {
    if (!reconnect_emitter(world, tracer, ps, base, pre, r)) return false;
  } else {
    Vertex xk;
    if (!rc_surface(world, base, dir, xk) || (hybrid && !pair_reconnectable(ps, base, pre, xk, dir, distance)) ||
        !reconnect_surface(world, tracer, ps, base, pre, xk, dir, r))
      return false;
  }
  out.rc_geometry = r.geometry;
  return shifted(r.f * r.mis, pre.pdf, base.replay_pdf / pre.pdf * r.jacobian, out, jacobian);
}

}  // namespace pt_detail

// The reconnection shift of `base` to the pixel whose primary surface is y1 (a valid surface): y_1
// connects to x_2. A path from a delta primary vertex has no reconnection vertex (k = 0) and is not
// shiftable (its inverse would need to reconnect from that delta vertex), so the shift fails as
// its inverse does.
template <class Tracer>
RESTIR_HD bool shift_reconnection(const PathWorld& world, const Tracer& tracer, const PathSettings& ps, const PathSample& base,
                                  const GSurface& y1, PathSample& out, float& jacobian) {
  using namespace pt_detail;
  if (base.rc == 0) return false;
  const ShiftPrefix pre{vertex_from_surface(y1)};  // k = 2: nothing to replay before y_1
  out = base;
  return reconnect(world, tracer, ps, base, false, pre, out, jacobian);
}

}  // namespace rl
