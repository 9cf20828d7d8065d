// The reservoir and streaming resampled importance sampling (RIS) — the core of every ReSTIR
// variant. Plain structs and small functions, no scene types: usable from host code now and from
// device code later (RESTIR_HD).
//
// Glossary (one field, one meaning; the names used everywhere in src/restir and the integrators):
//   target      p̂(x)      target function of the stored sample, in the reservoir's own domain
//   weight_sum  w_sum     running sum of resampling weights while streaming candidates
//   ucw         W         unbiased contribution weight of the stored sample, set by finalize()
//   confidence  M         confidence weight: how many candidates the reservoir stands for
//   mis_weight  m_i       resampling MIS weight of candidate i (the m_i sum to 1 over the sources)
//   jacobian    |∂T/∂x|   Jacobian determinant of a shift mapping T
//
// The GRIS estimator (Lin et al. 2022, "Generalized Resampled Importance Sampling", eq. 19-20;
// Bitterli et al. 2020, eq. 6): candidates x_i with resampling weights
//   w_i = m_i(x_i) · p̂(x_i) · W_i            (W_i = 1/p_i(x_i) for a fresh candidate of density p_i,
//                                              or a reused reservoir's ucw times the shift's jacobian),
// select Y with probability w_i / Σw, and W_Y = Σw / p̂(Y). Then E[f(Y) W_Y] = ∫ f wherever the m_i
// sum to one over the sources that can produce each x and p̂ > 0 wherever f ≠ 0.
#pragma once
#include <limits>

#include "core/math.h"

namespace rl::restir {

template <class Sample>
struct Reservoir {
  using SampleType = Sample;
  Sample sample{};
  float target = 0;      // p̂(sample) in the reservoir's own domain
  float weight_sum = 0;  // Σ w_i while streaming
  float ucw = 0;         // W, valid after finalize()
  float confidence = 0;  // M

  // True when a sample was selected and carries weight.
  RESTIR_HD bool has_sample() const { return ucw > 0 && target > 0; }
  // True when a candidate's target or weight was NaN or infinite: the integrand itself is broken
  // (a NaN in the scene, say). Such a reservoir is never reused; the integrator writes a
  // non-finite pixel and the render driver reports it (one policy for every integrator).
  RESTIR_HD bool non_finite() const { return std::isnan(weight_sum) || std::isnan(ucw); }
};

// Streams one candidate with resampling weight `weight` (weighted reservoir sampling, Chao 1982;
// Bitterli et al. 2020, Alg. 2). `u` is uniform in [0,1). Returns true when it replaced the sample.
template <class Sample>
RESTIR_HD inline bool stream(Reservoir<Sample>& r, const Sample& x, float target, float weight, float u) {
  if (!std::isfinite(target) || std::isnan(weight)) {
    r.weight_sum = std::numeric_limits<float>::quiet_NaN();  // surfaces as a non-finite pixel
    return false;
  }
  if (!(weight > 0) || !std::isfinite(weight)) return false;
  r.weight_sum += weight;
  if (u * r.weight_sum < weight) {
    r.sample = x;
    r.target = target;
    return true;
  }
  return false;
}

// Unbiased contribution weight W = Σw / (p̂(Y) · normalization) (GRIS eq. 20). The normalization is
// 1 when the MIS weights are inside the resampling weights; Bitterli et al. 2020's 1/Z variant
// (Alg. 6) passes Z there (see mis.h).
template <class Sample>
RESTIR_HD inline void finalize(Reservoir<Sample>& r, float normalization = 1.0f) {
  if (std::isnan(r.weight_sum)) {
    r.ucw = std::numeric_limits<float>::quiet_NaN();
    return;
  }
  const float denom = r.target * normalization;
  r.ucw = (r.target > 0 && denom > 0 && r.weight_sum > 0) ? r.weight_sum / denom : 0.0f;
  if (!std::isfinite(r.ucw)) r.ucw = 0;
}

// Resampling weight of one candidate (GRIS eq. 19): m_i · p̂(x) · W_i · |∂T/∂x|.
// A zero factor gives 0 (0 · ∞ from a degenerate shift is no sample); a NaN factor gives NaN, which
// stream() turns into a non-finite reservoir instead of hiding it; an infinite weight (degenerate
// jacobian) is dropped.
RESTIR_HD inline float resampling_weight(float mis_weight, float target, float ucw, float jacobian = 1.0f) {
  if (mis_weight == 0 || target == 0 || ucw == 0 || jacobian == 0) return 0.0f;
  const float w = mis_weight * target * ucw * jacobian;
  if (std::isnan(w)) return w;
  return std::isfinite(w) && w > 0 ? w : 0.0f;
}

// The largest confidence a reuse pass hands on. Confidence weights may be any positive numbers
// that every MIS evaluation of one combine() reads alike: the MIS weights built from them only
// need to sum to one (GRIS, Lin et al. 2022, eqs. 19-20), so saturating them leaves the estimator
// unbiased. It keeps the products in the MIS weights (M · p̂) inside float range: without an
// M-cap, spatial reuse makes M grow geometrically (about 1.3x a frame in the dynamic room), and it
// overflowed to infinity after ~270-340 frames, turning pixels into NaN. At 1e20 the newest
// candidates' share of such a history, ~1e-19, is nil either way.
inline constexpr float kMaxConfidence = 1e20f;

// M-capping (Bitterli et al. 2020 §6; thesis §4.2.4): a reused history reservoir keeps at most
// `cap` × the canonical reservoir's confidence, so the newest samples keep a relative weight of at
// least about 1/(cap + 1). cap <= 0 disables the cap.
RESTIR_HD inline float capped_confidence(float history, float canonical, float cap) {
  return cap > 0 ? std::min(history, cap * canonical) : history;
}

}  // namespace rl::restir
