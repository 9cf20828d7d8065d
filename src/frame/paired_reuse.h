// Paired (reciprocal) spatial reuse (Lin, Kettunen, Wyman 2026, "ReSTIR PT Enhanced", sec. 3),
// *.spatial_pairing = paired: the spatial round in two passes over pairing textures (pairing.h)
// instead of one over a spiral (reuse_pixel.h's spatial_pixel).
//
// Defensive pairwise MIS (mis.h, ReuseMis::pairwise) of canonical pixel c and neighbour j needs
// two shifted targets per neighbour: p̂_c(T_{j->c}(X_j)) |∂T_{j->c}| for j's candidate, and
// p̂_{<-j}(X_c) = p̂_j(T_{c->j}(X_c)) |∂T_{c->j}| for c's own MIS weight. When j is c's partner and
// c is j's (the pairing is an involution), pixel j's round needs exactly the same two numbers with
// the roles exchanged. So:
//   1. paired_shift_pixel: every pixel p shifts its own sample into each accepted partner's domain
//      and stores PairedShift{p̂_q(T_{p->q}(X_p)), |∂T_{p->q}/∂X_p|} -- one shift per neighbour
//      (spatial_pixel makes two);
//   2. paired_resample_pixel: every pixel combines its reservoir with its partners' from those
//      numbers alone -- its own slot gives p̂_{<-j}(X_c) = target x jacobian, the partner's slot the
//      candidate's target and jacobian -- and shifts only the sample it selects.
// The resampling weights, the MIS weights and the random numbers are those of restir::combine()
// over the same inputs, so the result has combine()'s distribution (and is unbiased for the same
// reasons). Both passes must accept the same partners, which the symmetric similarity test
// (similar_pair) guarantees: a partner that only one side accepts would leave the other's MIS
// weights summing to less than one (tests/integrators: the planted one-sided test is caught).
#pragma once
#include "frame/pairing.h"
#include "frame/reuse_pixel.h"

namespace rl {

// Pixel p's sample shifted into partner q's domain (slot t of pixel p): q's target there and the
// shift's jacobian. jacobian 0: no shift (no accepted partner, no sample, or the shift failed).
struct PairedShift {
  float target = 0;
  float jacobian = 0;
};

// The similarity test of a pair, the same from either side: the depth difference against the
// nearer depth (spatial_pixel's test measures it against the canonical pixel's own).
RESTIR_HD inline bool similar_pair(const GPacked& a, const GPacked& b, float depth_threshold, float normal_threshold_deg) {
  if (!a.valid() || !b.valid()) return false;
  if (std::fabs(a.depth - b.depth) > depth_threshold * std::max(std::min(a.depth, b.depth), 1e-6f)) return false;
  return dot(packed_shading_normal(a), packed_shading_normal(b)) >= std::cos(normal_threshold_deg * kPi / 180.0f);
}

// p̂_{<-i} of neighbour i's own sample when its stored target cannot stand for it (mis.h,
// Bridge::stored_target_valid): shift it here and evaluate its domain's target at the result.
template <class Bridge, class Res>
RESTIR_HD float paired_own_target(const Bridge& bridge, int i, const Res& in) {
  typename Res::SampleType x;
  float jacobian = 1;
  if (!bridge.shift_to_canonical(i, in.sample, x, jacobian)) return 0;
  return bridge.target_from(i, x);
}

// What both passes read: the textures, this round's streams and the rejection settings.
struct PairedRound {
  PairingView pairing;
  const PairingTransform* transforms = nullptr;  // texture t's in this round (PairingView::transform)
  ReuseFrame f;
  int round = 0;
  // Tests only (planted_bias.h): the shift pass skips partners farther from the camera than the
  // pixel, so only one side of each pair shifts while the resampling pass accepts both
  // (one_sided); the partner's offset is read without the transform's transpose, which breaks the
  // involution (broken).
  bool one_sided = false, broken = false;

  // Pixel (x, y)'s partner through texture t, or false when it is off screen or not similar.
  RESTIR_HD bool accepted_partner(const ReuseOptions& rp, const GBufferView& g, int t, int x, int y, int& qx, int& qy,
                                  bool resampling) const {
    pairing.partner(t, transforms[t], x, y, qx, qy, !broken);
    if (qx < 0 || qy < 0 || qx >= g.width || qy >= g.height || !g.packed(qx, qy).valid()) return false;
    if (one_sided && !resampling && g.packed(qx, qy).depth > g.packed(x, y).depth) return false;
    if (!rp.similarity_rejection) return true;
    return similar_pair(g.packed(x, y), g.packed(qx, qy), rp.depth_threshold, rp.normal_threshold);
  }
};

// Whether the bridge's shift of `sample` replays part of a path (ReSTIR PT's random replay, or a
// hybrid prefix): the shifts replay compaction defers. Bridges without such shifts have no
// needs_replay and nothing is deferred.
template <class Bridge, class Sample>
RESTIR_HD bool shift_needs_replay(const Bridge& bridge, const Sample& sample) {
  if constexpr (requires { bridge.needs_replay(sample); }) {
    return bridge.needs_replay(sample);
  } else {
    (void)bridge, (void)sample;
    return false;
  }
}

// Slot t of pixel (x, y) in pass 1: its sample shifted into partner t's domain, into
// shifts[p * k + t] (a pixel's k slots side by side: pass 2 reads its own in one cache line).
// deferred (replay compaction, pt.replay_compaction): a shift that needs a replay is not made but
// flagged in deferred[p * k + t], for paired_replay_slot; null: every shift is made here.
template <class Res, class MakeBridge>
RESTIR_HD void paired_shift_slot(const ReuseOptions& rp, const GBufferView& g, const Res* reservoirs, PairedShift* shifts,
                                 const MakeBridge& make_bridge, const PairedRound& pr, int x, int y, int t, const ReuseColor& color,
                                 uint8_t* deferred = nullptr) {
  const size_t k = size_t(pr.pairing.count), p = size_t(y) * size_t(g.width) + size_t(x), slot = p * k + size_t(t);
  const GPacked& own = g.packed(x, y);
  const Res& r = reservoirs[p];
  PairedShift& out = shifts[slot];
  out = PairedShift{};
  if (deferred) deferred[slot] = 0;
  int qx, qy;
  if (!own.valid() || !r.has_sample() || !pr.accepted_partner(rp, g, t, x, y, qx, qy, false)) return;
  // The partner as the canonical domain (0) and this pixel as the source (1).
  const GSurface partner = g.at(qx, qy);
  const GPacked* packed[2] = {nullptr, &own};
  auto bridge = make_bridge(SurfaceList{&partner, packed, g.materials, g.eye}, 2, false);
  if (deferred && shift_needs_replay(bridge, r.sample)) {
    deferred[slot] = 1;
    return;
  }
  typename Res::SampleType shifted;
  float jacobian = 1;
  if (!bridge.shift_to_canonical(1, r.sample, shifted, jacobian)) return;
  out.target = bridge.target_from(0, shifted);
  out.jacobian = jacobian > 0 ? jacobian : 0.0f;
  if constexpr (requires { bridge.color(shifted); }) {
    if (color.shifts) color.shifts[slot] = bridge.color(shifted);
  }
}

// Pass 1 at pixel (x, y): its sample shifted into each accepted partner's domain (paired_shift_slot).
template <class Res, class MakeBridge>
RESTIR_HD void paired_shift_pixel(const ReuseOptions& rp, const GBufferView& g, const Res* reservoirs, PairedShift* shifts,
                                  const MakeBridge& make_bridge, const PairedRound& pr, int x, int y, const ReuseColor& color = {},
                                  uint8_t* deferred = nullptr) {
  for (int t = 0; t < pr.pairing.count; ++t) paired_shift_slot(rp, g, reservoirs, shifts, make_bridge, pr, x, y, t, color, deferred);
}

// Replay compaction's second half of pass 1: the deferred slots (listed by Exec::select, in any
// order) shifted as pass 1 would have; each writes only its own slot, so the result does not
// depend on the list's order.
template <class Res, class MakeBridge>
RESTIR_HD void paired_replay_slot(const ReuseOptions& rp, const GBufferView& g, const Res* reservoirs, PairedShift* shifts,
                                  const MakeBridge& make_bridge, const PairedRound& pr, uint32_t slot, const ReuseColor& color) {
  const uint32_t k = uint32_t(pr.pairing.count), p = slot / k;
  const int x = int(p % uint32_t(g.width)), y = int(p / uint32_t(g.width));
  paired_shift_slot(rp, g, reservoirs, shifts, make_bridge, pr, x, y, int(slot % k), color);
}

// Pass 2's inputs at pixel p: 0 the pixel itself, then its accepted partners with the texture
// (slot) and pixel (at) of each.
template <class Res>
struct PairedInputs {
  const GPacked* surfaces[PairingView::kMaxTextures + 1];  // [0] unused: the pass unpacks its own
  const Res* inputs[PairingView::kMaxTextures + 1];
  int slot[PairingView::kMaxTextures + 1];
  size_t at[PairingView::kMaxTextures + 1];
};

// Fills `in` for pixel (x, y) (a valid surface) and returns the input count; counts the partners
// tried and rejected for the debug views.
template <class Res>
RESTIR_HD int paired_inputs(const ReuseOptions& rp, const GBufferView& g, const Res* reservoirs, const PairedShift* shifts,
                            const PairedRound& pr, const ReuseDebugView& dbg, int x, int y, PairedInputs<Res>& in) {
  const size_t k = size_t(pr.pairing.count), p = size_t(y) * size_t(g.width) + size_t(x);
  in.surfaces[0] = nullptr, in.inputs[0] = &reservoirs[p], in.at[0] = p, in.slot[0] = -1;
  int n = 1;
  for (int t = 0; t < pr.pairing.count; ++t) {
    ++dbg.tried[p];
    int qx, qy;
    if (!pr.accepted_partner(rp, g, t, x, y, qx, qy, true)) {
      ++dbg.rejected[p];
      continue;
    }
    in.at[n] = size_t(qy) * size_t(g.width) + size_t(qx);
    in.surfaces[n] = &g.packed(qx, qy), in.inputs[n] = &reservoirs[in.at[n]], in.slot[n] = t;
    ++n;
  }
#ifndef __CUDA_ARCH__
  // The partners' reservoirs and shift slots are up to a few sigma rows away (cache misses, as in
  // spatial_pixel): fetch them all before the first is read.
  for (int i = 1; i < n; ++i) {
    prefetch_lines(in.inputs[i], sizeof(Res));
    prefetch_lines(shifts + in.at[i] * k + size_t(in.slot[i]), sizeof(PairedShift));
  }
#else
  (void)shifts, (void)k;
#endif
  return n;
}

// Pass 2 at pixel (x, y): its reservoir combined with its accepted partners' (rp.spatial_mis, one
// of mis.h's pairwise family: defensive pairwise or the ratio weights, as restir::combine), into next.
template <class Res, class MakeBridge>
RESTIR_HD void paired_resample_pixel(const ReuseOptions& rp, const GBufferView& g, const Res* reservoirs, const PairedShift* shifts,
                                     Res* next, const MakeBridge& make_bridge, const PairedRound& pr, const ReuseDebugView& dbg, int x,
                                     int y, const ReuseColor& color = {}) {
  const size_t k = size_t(pr.pairing.count), p = size_t(y) * size_t(g.width) + size_t(x);
  const GSurface cur = g.at(x, y);
  next[p] = reservoirs[p];
  if (color.out) color.out[p] = Rgb(0);
  if (!cur.valid) return;
  PairedInputs<Res> in_;
  const int n = paired_inputs(rp, g, reservoirs, shifts, pr, dbg, x, y, in_);
  const SurfaceList surfaces{&cur, in_.surfaces, g.materials, g.eye};
  const Res* const* inputs = in_.inputs;
  const int* slot = in_.slot;
  const size_t* at = in_.at;
  auto bridge = make_bridge(surfaces, n, false);
  Res out;
  float m_sum = 0;
  for (int i = 0; i < n; ++i) m_sum += inputs[i]->confidence;
  out.confidence = restir::kMaxConfidence < m_sum ? restir::kMaxConfidence : m_sum;
  if (!(m_sum > 0)) {
    next[p] = out;
    return;
  }
  const float m_c = inputs[0]->confidence, m_rest = m_sum - m_c;
  const restir::MisWeights weights = reuse_weights(rp.spatial_mis, rp, pr.f);
  if (inputs[0]->non_finite()) out.weight_sum = std::numeric_limits<float>::quiet_NaN();
  Pcg32 rng = spatial_stream(pr.f, pr.round, uint32_t(p));
  (void)rng.next_float();  // spatial_pixel's spiral rotation: the same streams for the same inputs
  int selected = -1, failed = 0;
  for (int i = 0; i < n; ++i) {
    const Res& in = *inputs[i];
    // Input i's sample in this pixel's domain: target p0 = p̂_c(x) and jacobian |∂T_{i->c}|.
    PairedShift s = i == 0 ? PairedShift{in.target, 1.0f} : shifts[at[i] * k + size_t(slot[i])];
    if constexpr (requires { bridge.stored_target_valid(0); }) {
      if (i == 0 && !bridge.stored_target_valid(0)) s.target = bridge.target_from(0, in.sample);
    }
    if (!in.has_sample() || (i > 0 && !(s.jacobian > 0))) {
      if (i > 0 && in.has_sample()) ++failed;
      (void)rng.next_float();
      continue;
    }
    float m;
    if (i == 0) {  // m_c: mis.h's canonical weight, p̂_{<-j}(X_c) from this pixel's own slots
      const PairedShift* own = shifts + p * k;
      m = restir::detail::pair_canonical_base(weights, m_c, m_sum, m_rest);
      for (int j = 1; j < n; ++j) {
        const PairedShift o = own[slot[j]];
        m += restir::detail::pair_canonical_term(weights, inputs[j]->confidence, m_sum, m_c, m_rest, s.target, o.target * o.jacobian);
      }
      m = m > 0 ? m : 0.0f;
    } else {  // m_j: the neighbour's own target p̂_j(X_j) over the jacobian is p̂_{<-j} at x (mis.h)
      float own_target = in.target / s.jacobian;
      if constexpr (requires { bridge.stored_target_valid(i); }) {
        if (!bridge.stored_target_valid(i)) own_target = paired_own_target(bridge, i, in);
      } else {
        own_target = paired_own_target(bridge, i, in);
      }
      m = restir::detail::pair_neighbor_weight(weights, in.confidence, m_sum, m_c, m_rest, s.target, own_target);
    }
    const float w = restir::resampling_weight(m, s.target, in.ucw, s.jacobian);
    if constexpr (requires { bridge.color(in.sample); }) {  // RGB weights: as restir::combine's (mis.h)
      if (color.out && w > 0)
        color.out[p] += restir::color_term(i == 0 ? bridge.color(in.sample) : color.shifts[at[i] * k + size_t(slot[i])], w,
                                           color.planted_input_target ? in.target : s.target);
    }
    if (restir::stream(out, in.sample, s.target, w, rng.next_float())) selected = i;
  }
  // The selected neighbour's sample as this pixel sees it: shifted once, here (the target is the
  // partner's pass-1 value, the same shift).
  if (selected > 0) {
    float jacobian = 1;
    typename Res::SampleType shifted;
    // It succeeded in pass 1 and shifts are deterministic; a failure here would be a bridge bug.
    if (bridge.shift_to_canonical(selected, out.sample, shifted, jacobian)) out.sample = shifted;
    dbg.source[p] = 2;
  }
  dbg.rejected[p] += uint16_t(failed);
  restir::finalize(out);
  next[p] = out;
}

}  // namespace rl
