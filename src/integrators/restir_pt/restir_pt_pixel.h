// ReSTIR PT's per-pixel stages: the shift behind its one switch, the reuse bridge and the shading,
// RESTIR_HD over a FrameWorld and its Tracer (frame_world.h), so that every backend runs one
// implementation of every path density, MIS weight and Jacobian. The walks and the initial
// resampling are walk.h's; each shift mapping has its own file (shift_reconnection.h,
// shift_random_replay.h, shift_hybrid.h).
#pragma once
#include "frame/frame_world.h"
#include "frame/planted_bias.h"
#include "frame/reuse_pixel.h"
#include "integrators/restir_pt/shift_hybrid.h"
#include "integrators/restir_pt/shift_random_replay.h"
#include "integrators/restir_pt/shift_reconnection.h"
#include "integrators/restir_pt/walk.h"

namespace rl {

// Shifts `base` to the pixel whose primary surface is `y1` with the shift mapping pt.shift (the
// one its walk described it for). Returns false if the shift fails (different path structure,
// invalid vertex, occlusion, zero contribution); else `out` lives in the new domain and
// jacobian = |∂ȳ/∂x̄|.
template <class Tracer>
RESTIR_HD bool shift_path(const PathWorld& world, const Tracer& tracer, const PathSettings& ps, const PathSample& base, const GSurface& y1,
                          PathSample& out, float& jacobian) {
  if (!y1.valid || base.length < 2 || world.lights.empty()) return false;
  switch (ps.pt.shift) {
    case ShiftMapping::reconnection: return shift_reconnection(world, tracer, ps, base, y1, out, jacobian);
    case ShiftMapping::random_replay: return shift_random_replay(world, tracer, ps, base, y1, out, jacobian);
    case ShiftMapping::hybrid: return shift_hybrid(world, tracer, ps, base, y1, out, jacobian);
  }
  return false;
}

// The CPU backend's copies of initial_path_reservoir and shift_path compiled for the host's widest
// instruction set (pt_path.cpp, core/widest.h): calls with an EmbreeTracer pick these overloads.
PathReservoir initial_path_reservoir(const PathWorld& world, const EmbreeTracer& tracer, const PathSettings& ps, const GSurface& s,
                                     uint64_t seed, int candidates, const LightTileView& tile = {});
bool shift_path(const PathWorld& world, const EmbreeTracer& tracer, const PathSettings& ps, const PathSample& base, const GSurface& y1,
                PathSample& out, float& jacobian);

// The bridge of mis.h for paths: shifts evaluate the path at the other pixel's primary hit.
// In an animated scene's temporal pass (pt.history_scene = previous) domain 1 is the previous
// frame: the history's paths were traced in that frame's scene, and a path is shifted between the
// frames by random replay -- its random numbers re-traced from the other frame's primary hit in
// that frame's scene (FrameWorld's previous world, its BVH and its lights). The map is the
// identity in primary sample space, so the pair of frames is a valid shift with |∂ȳ/∂x̄| =
// p(x̄)/p(ȳ), each density taken in its own scene (GRIS, Lin et al. 2022, §6.1), and the MIS
// weights see each domain's own target, which vanishes wherever that frame could not have drawn
// the path (a light switched off, an occluder moved in): the weights stay a partition of unity
// over the supports (GRIS §5), which is what unbiasedness needs.
template <class Tracer>
struct PtBridges;

// Queued: the bridge of a queued reuse pass (ray_slots.h; see DiBridge).
template <class Tracer, bool Queued = false>
struct PtBridge {
  const PtBridges<Tracer>* b;
  SurfaceList surfaces;  // surfaces[i] = domain i's primary surface, 0 = canonical
  bool history;                     // domain 1 lives in the previous frame's scene (FrameWorld::previous_world)
  // Domain 1 is last frame's pixel evaluated in this frame's scene (pt.history_scene = current in an
  // animated scene): its stored target was computed in the other scene.
  bool history_in_other_scene;
  RayCursor* cursor;                // Queued: the pixel's slots
  mutable int shifting = 0;         // the input combine() is weighing (for planted biases only)
  // Another domain's stored target is p̂_i of its own sample y, computed at its own primary hit in
  // the scene it was made in (an animated history's too, as long as each domain's target is
  // evaluated in its own frame's scene), and shift_path maps x = T_{i→0}(y) back onto y: the prefix
  // is replayed with y's random numbers from the same primary hit, x keeps y's reconnection vertex
  // and suffix, and the hybrid shift's invertibility check (GRIS §7.2) makes both walks choose the
  // same reconnection index. So combine() reads p̂_i(y) / jacobian (mis.h) instead of shifting the
  // path back: one shift, and its rays, fewer per neighbour, as in Lin's reference implementation.
  // Without the check, or under a planted bias of the tests (which acts in target_from), the
  // target is evaluated.
  RESTIR_HD bool stored_target_valid(int i) const {
    return i > 0 && b->ps.check_invertibility && b->ps.retest_on_offset && b->ps.retest_forced_nee && !b->planted_on && !(i == 1 && history_in_other_scene);
  }
  RESTIR_HD bool shift_in(int i, const PathSample& x, const GSurface& to, PathSample& y, float& jacobian) const {
    const FrameWorld<Tracer>& fw = b->fw;
    // The previous frame's rays are not queued (the queue holds this frame's).
    if (i == 1 && history) return shift_path(fw.previous_world, pass_tracer<Queued>(fw.previous_tracer, nullptr), b->ps, x, to, y, jacobian);
    return shift_path(fw.world, pass_tracer<Queued>(fw.tracer, cursor), b->ps, x, to, y, jacobian);
  }
  RESTIR_HD bool shift_to_canonical(int i, const PathSample& y, PathSample& x, float& jacobian) const {
    shifting = i;
    const bool ok = shift_in(0, y, surfaces[0], x, jacobian);
    if (b->planted_on) jacobian *= b->planted.jacobian_scale;
    return ok;
  }
  // F(x), RGB, of a path already in the canonical domain (RGB resampling weights, mis.h).
  RESTIR_HD Rgb color(const PathSample& x) const { return x.contribution; }
  // Whether shifting y replays part of its path (traces from the offset primary hit before any
  // reconnection): random replay always; the hybrid shift unless y reconnects at x_2, right after
  // the primary hit; the reconnection shift never. Replay compaction (paired_reuse.h) defers these.
  RESTIR_HD bool needs_replay(const PathSample& y) const {
    switch (b->ps.pt.shift) {
      case ShiftMapping::reconnection: return false;
      case ShiftMapping::random_replay: return true;
      case ShiftMapping::hybrid: return y.rc != 2;
    }
    return true;
  }
  RESTIR_HD float target_from(int i, const PathSample& x) const {
    if (i == 0) return luminance(x.contribution);  // x already lives in the canonical domain
    // Every shift writes its output whole (out = base) before anything reads it, and it is read
    // only where the shift succeeded: left unwritten until then (zeroing it per call showed in perf).
    union Shifted {
      PathSample y;
      RESTIR_HD Shifted() {}
    } shifted;
    float jacobian;
    if (!shift_in(i, x, surfaces[i], shifted.y, jacobian)) return 0;
    float t = luminance(shifted.y.contribution) * jacobian;
    if (b->planted_on) t *= b->planted.jacobian_scale * (i == shifting ? b->planted.own_target_scale : 1.0f);
    return t;
  }
};

// The bridges of one frame, made per pixel by the reuse stages (reservoir_chain.h).
template <class Tracer>
struct PtBridges {
  FrameWorld<Tracer> fw;
  PathSettings ps;
  bool history_in_previous;  // pt.history_scene = previous
  PlantedBias planted;       // tests only (planted_bias.h), when planted_on
  bool planted_on;
  // pt.replay_compaction: paired reuse makes the shifts that replay in a pass of their own.
  bool compact_replays() const { return ps.pt.replay_compaction; }
  // pt.history_scene = current evaluates the history in this frame's scene even where the previous
  // one is kept (for pt.direct = restir-di's ReSTIR DI).
  RESTIR_HD bool past(bool temporal) const { return temporal && fw.has_previous && history_in_previous; }
  RESTIR_HD PtBridge<Tracer> operator()(const SurfaceList& surfaces, int, bool temporal) const {
    return {this, surfaces, past(temporal), temporal && !past(temporal) && fw.animated, nullptr};
  }
  RESTIR_HD PtBridge<Tracer, true> operator()(const SurfaceList& surfaces, int, bool temporal, RayCursor* cursor) const {
    return {this, surfaces, past(temporal), temporal && !past(temporal) && fw.animated, cursor};
  }
};

// The reconnection-depth debug view's value: the final path's reconnection vertex k (0: none).
RESTIR_HD inline int reconnection_depth_of(const PathReservoir& r) { return r.has_sample() ? r.sample.rc : 0; }

// A pixel's radiance: the emission its primary hit sees (unless ReSTIR DI adds it, pt.direct =
// restir-di) + f(Y) W_Y of its reservoir's path, W_Y its unbiased contribution weight (Lin et al. 2022),
// or, with pt.rgb_weights, `color`: the last spatial round's Σ m_i F(Y_i) W_i |J_i| (mis.h,
// CombineInfo::color), E[f(Y) W_Y] over that round's selection. A reservoir a (biased) boiling
// filter emptied afterwards contributes nothing either way.
RESTIR_HD inline Rgb pt_shade(const GSurface& sf, const PathReservoir& r, bool direct_from_di, const Rgb* color = nullptr) {
  Rgb L = direct_from_di ? Rgb(0) : sf.le;
  if (sf.valid && r.has_sample()) L += color ? *color : r.sample.contribution * r.ucw;
  mark_non_finite(r, L);
  return L;
}

}  // namespace rl
