// The hybrid shift (GRIS, Lin et al. 2022, §7.2): random replay of the base path's prefix up to
// y_{k-1}, then reconnection to x_k, where k is the first reconnectable vertex pair (x_{k-1}, x_k)
// (reconnection_index, walk.h: both rough and |x_k - x_{k-1}| >= pt.distance_threshold, or under
// pt.reconnection = footprint ReSTIR PT Enhanced's dual ray footprint, sec. 4); a path without such a
// pair replays whole. Invertible only if the offset path's own walk would choose the same k: so no
// replayed pair may pass the criterion (replay_prefix's check), and y_{k-1} and the reconnected
// segment must (reconnect's `hybrid`) -- the check a planted bias of the tests removes
// (PathSettings::check_invertibility).
#pragma once
#include "integrators/restir_pt/shift_random_replay.h"
#include "integrators/restir_pt/shift_reconnection.h"

namespace rl {

template <class Tracer>
RESTIR_HD bool shift_hybrid(const PathWorld& world, const Tracer& tracer, const PathSettings& ps, const PathSample& base, const GSurface& y1,
                            PathSample& out, float& jacobian) {
  using namespace pt_detail;
  const int k = base.rc;
  ShiftPrefix pre{vertex_from_surface(y1)};
  pre.footprint = footprint_threshold(ps, y1);  // the offset path's own primary footprint
  // A planted bias of the tests (PathSettings::retest_on_offset) tests a direction-dependent
  // criterion (the footprints, the pdf proxy) on the base path only.
  const bool retest = !criterion_depends_on_direction(ps) || ps.retest_on_offset;
  const bool check = ps.check_invertibility && retest;
  const int last = k > 0 ? k - 1 : base.length - 1;  // the vertex that connects to x_k / samples the last vertex
  if (!replay_prefix(world, tracer, ps, base, last, check, pre)) return false;
  out = base;
  if (k == 0) return replay_last_vertex(world, tracer, ps, base, last, check, pre, out, jacobian);
  return reconnect(world, tracer, ps, base, retest, pre, out, jacobian);
}

}  // namespace rl
