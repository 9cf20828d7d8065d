// Reuse: combining a canonical reservoir with reservoirs of other domains (neighbouring pixels,
// the previous frame) through a narrow bridge, with the resampling MIS weights of the literature.
// One routine serves temporal and spatial reuse of ReSTIR DI, GI and PT; the integrators only
// supply the bridge (target functions and shift mappings of their domain).
//
// Bridge (any type with these members; `i` indexes the inputs, 0 is the canonical domain):
//   // x = T_{i→0}(y): a sample of source i shifted into the canonical domain; false if the shift
//   // fails. jacobian = |∂T_{i→0}/∂y| (1 for the identity shift of ReSTIR DI on area measure).
//   bool shift_to_canonical(int i, const Sample& y, Sample& x, float& jacobian) const;
//   // p̂_{←i}(x): source i's target function at the canonical-domain sample x shifted back to
//   // domain i, times that shift's jacobian |∂T_{0→i}/∂x| (0 when the shift fails). For i == 0: p̂_0(x).
//   float target_from(int i, const Sample& x) const;
//   // Optional: true when input i's stored target is p̂_i(y) of its own sample y, computed in domain i
//   // with the function target_from(i, ·) uses, and T_{0→i} inverts T_{i→0} wherever the latter
//   // succeeds. Then p̂_{←i}(x) = p̂_i(T_{0→i}(x)) |∂T_{0→i}/∂x| at x = T_{i→0}(y) is
//   // p̂_i(y) / |∂T_{i→0}/∂y| (the inverse function theorem applied to p̂_{←i} of GRIS, Lin et al.
//   // 2022, eq. 22, which is defined through the inverse shift), and combine() reads
//   // inputs[i]->target / jacobian instead of shifting x back (a whole path and its rays in ReSTIR
//   // PT; a shadow ray in ReSTIR DI, whose identity shift has jacobian 1, and in ReSTIR GI). RTXDI
//   // reads the stored target pdf the same way, and the ReSTIR PT reference (Lin's pairwise MIS)
//   // divides the neighbour's stored integrand by the shift's Jacobian.
//   bool stored_target_valid(int i) const;
#pragma once
#include <algorithm>
#include <cmath>
#include <span>

#include "core/rng.h"
#include "restir/reservoir.h"

namespace rl::restir {

// Resampling MIS weights m_i for reuse.
enum class ReuseMis {
  constant,             // m_i = M_i / ΣM. Biased whenever the domains' supports differ (shown in tests).
  one_over_z,           // Bitterli et al. 2020, Alg. 6: resample with M_i·p̂_0·W_i, then W = Σw / (p̂_0(Y)·Z(Y)),
                        // Z = Σ of M_j over the sources whose p̂_{←j}(Y) > 0. Unbiased, O(N).
  generalized_balance,  // Talbot 2005 / GRIS eq. 22: m_i(x) = M_i p̂_{←i}(x) / Σ_j M_j p̂_{←j}(x). Unbiased, O(N²).
  pairwise,             // Bitterli 2022 (thesis §9.1.3) / Wyman et al. 2023 course notes §7: defensive,
                        // confidence-weighted pairwise MIS against the canonical sample. Unbiased, O(N).
  symmetric_ratio,      // Pan et al. 2024 ("Enhancing Spatiotemporal Resampling with a Novel MIS Weight",
                        // eq. 15): pairwise, with the ratio of the two targets replaced by their
                        // similarity d = min(p̂_0/p̂_←j, p̂_←j/p̂_0)^β. Unbiased, O(N).
  asymmetric_ratio,     // Pan et al. 2024, eq. 16: a neighbour's weight from d, the canonical's the rest
                        // (1 - Σ_j m_j). Unbiased, O(N).
};

// The resampling MIS weights of one reuse pass: which, and the ratio weights' exponent β.
struct MisWeights {
  ReuseMis kind = ReuseMis::pairwise;
  float ratio_exponent = 2;  // β of symmetric_ratio / asymmetric_ratio (Pan et al. 2024 use 2)
  // Tests only (PlantedBias::ratio_canonical_symmetric): asymmetric_ratio's canonical weight taken
  // from symmetric_ratio's formula, so the weights no longer sum to one.
  bool planted_canonical_symmetric = false;
  RESTIR_HD constexpr MisWeights(ReuseMis k = ReuseMis::pairwise, float beta = 2, bool planted = false)  // NOLINT: from ReuseMis
      : kind(k), ratio_exponent(beta), planted_canonical_symmetric(planted) {}
};

// Everything a reuse pass reports besides the new reservoir (debug views, tests).
struct CombineInfo {
  int selected = -1;           // which input the output sample came from (-1: none)
  int failed_shifts = 0;       // inputs whose sample could not be shifted to the canonical domain
  // RGB resampling weights (ReSTIR PT Enhanced, Lin, Kettunen, Wyman 2026, sec. 6.3): with
  // want_color and a bridge that has color(x) (the integrand F(x), RGB, in the canonical domain),
  // color = Σ_i m_i F(Y_i) W_i |∂T_i/∂X_i| = Σ_i w_i F(Y_i) / p̂(Y_i) over the inputs. It is
  // E[F(Y) W_Y | the inputs] over the selection of Y (W_Y = Σw / p̂(Y), GRIS eq. 20), so shading
  // with it instead of F(Y) W_Y is unbiased with less colour noise: p̂ is a luminance, the
  // selection does not importance-sample chroma, the sum averages it over the inputs. The MIS
  // weights must be inside the w_i (not ReuseMis::one_over_z, which normalises Y alone).
  bool want_color = false;
  Rgb color{0};
  // Tests only (PlantedBias::color_input_target): divides w_i by the input's own-domain target
  // p̂_i(X_i) instead of p̂(Y_i) (the two domains mixed up).
  bool color_input_target = false;
};

// One input's term of CombineInfo::color: F(Y_i) w_i / p̂(Y_i), nothing where w_i or p̂ is 0 (the
// paired resampling pass, paired_reuse.h, sums the same terms).
RESTIR_HD inline Rgb color_term(Rgb f, float w, float target) { return w > 0 && target > 0 ? f * (w / target) : Rgb(0); }

namespace detail {
// Pairwise MIS (confidence-weighted, defensive): with M_c the canonical confidence, R = ΣM − M_c,
//   m_c(x) = M_c/ΣM + Σ_j (M_j/ΣM) · M_c p̂_0(x) / (M_c p̂_0(x) + R p̂_{←j}(x))
//   m_j(x) = (M_j/ΣM) · R p̂_{←j}(x) / (R p̂_{←j}(x) + M_c p̂_0(x))
// For every x with p̂_0(x) > 0 the weights of all sources sum to one (each pair's two fractions sum to 1).
RESTIR_HD inline float pairwise_fraction(float a, float b) { return a + b > 0 ? a / (a + b) : 0.0f; }
// m_c's term for neighbour j: (M_j/ΣM) · M_c p̂_0(x) / (M_c p̂_0(x) + R p̂_{←j}(x)). p_from_j = p̂_{←j}(x).
RESTIR_HD inline float pairwise_canonical_term(float m_j, float m_sum, float m_c, float p0, float m_rest, float p_from_j) {
  return m_j / m_sum * pairwise_fraction(m_c * p0, m_rest * p_from_j);
}
// m_j(x) = (M_j/ΣM) · R p̂_{←j}(x) / (R p̂_{←j}(x) + M_c p̂_0(x)). p_from_j = p̂_{←j}(x).
RESTIR_HD inline float pairwise_neighbor_weight(float m_j, float m_sum, float m_rest, float p_from_j, float m_c, float p0) {
  return m_j / m_sum * pairwise_fraction(m_rest * p_from_j, m_c * p0);
}

// The ratio weights of Pan et al. 2024. The paper's text was not available to us; the weights are
// written from its equations as a public implementation names them (eqs. 15, 16), generalised
// with confidences as Bitterli's pairwise MIS is, and checked here from first principles: with
// M_c the canonical confidence, R = ΣM − M_c, d_j(x) = d(p̂_0(x), p̂_{←j}(x)) >= 0,
//   symmetric:  m_j(x) = M_j d_j / (M_c + R d_j),   m_c(x) = Σ_j (M_j/R) · M_c / (M_c + R d_j)
//   asymmetric: m_j(x) = M_j d_j / (M_c + R d_j) where p̂_0(x) <= p̂_{←j}(x), else M_j d_j / (M_c + R);
//               m_c(x) = 1 − Σ_j m_j(x)
// Both sum to one over the techniques for every x (symmetric: each pair's two fractions sum to
// M_j/R; asymmetric: by construction, with m_c >= 0 since m_j < M_j/R), whatever function d is,
// and m_j(x) = 0 where domain j cannot produce x (p̂_{←j}(x) = 0 gives d = 0): the conditions of
// GRIS (Lin et al. 2022, eqs. 19-20) for an unbiased reuse. d only decides how well they weigh.
// d(a, b) = min(a/b, b/a)^β, 0 when either target is 0: 1 for equal targets, falling with their ratio.
RESTIR_HD inline float ratio_difference(float a, float b, float beta) {
  if (!(a > 0) || !(b > 0)) return 0;
  const float r = a < b ? a / b : b / a;
  return beta == 2.0f ? r * r : powf(r, beta);
}
RESTIR_HD inline float safe_fraction(float num, float den) { return den > 0 ? num / den : 0.0f; }

// m_j(x) of neighbour j for the pairwise family (pairwise, symmetric_ratio, asymmetric_ratio), at
// x with p0 = p̂_0(x) and pj = p̂_{←j}(x).
RESTIR_HD inline float pair_neighbor_weight(const MisWeights& w, float m_j, float m_sum, float m_c, float m_rest, float p0, float pj) {
  if (w.kind == ReuseMis::pairwise) return pairwise_neighbor_weight(m_j, m_sum, m_rest, pj, m_c, p0);
  const float d = ratio_difference(p0, pj, w.ratio_exponent);
  const bool shrink = w.kind == ReuseMis::symmetric_ratio || p0 <= pj;
  return safe_fraction(m_j * d, m_c + m_rest * (shrink ? d : 1.0f));
}
// m_c(x) = base + Σ_j term_j(x) for the pairwise family: the base, then neighbour j's term at the
// canonical sample x (p0 = p̂_0(x), pj = p̂_{←j}(x)).
RESTIR_HD inline float pair_canonical_base(const MisWeights& w, float m_c, float m_sum, float m_rest) {
  if (w.kind == ReuseMis::pairwise) return m_c / m_sum;
  if (w.kind == ReuseMis::asymmetric_ratio && !w.planted_canonical_symmetric) return 1;
  return m_rest > 0 ? 0.0f : 1.0f;  // symmetric: no neighbour with confidence leaves the canonical alone
}
RESTIR_HD inline float pair_canonical_term(const MisWeights& w, float m_j, float m_sum, float m_c, float m_rest, float p0, float pj) {
  if (w.kind == ReuseMis::pairwise) return pairwise_canonical_term(m_j, m_sum, m_c, p0, m_rest, pj);
  if (w.kind == ReuseMis::asymmetric_ratio && !w.planted_canonical_symmetric)
    return -pair_neighbor_weight(w, m_j, m_sum, m_c, m_rest, p0, pj);
  if (!(m_rest > 0)) return 0;
  return m_j / m_rest * safe_fraction(m_c, m_c + m_rest * ratio_difference(p0, pj, w.ratio_exponent));
}
RESTIR_HD inline bool pairwise_family(ReuseMis m) {
  return m == ReuseMis::pairwise || m == ReuseMis::symmetric_ratio || m == ReuseMis::asymmetric_ratio;
}

// p̂_{←i} of input i's own sample shifted to x = T_{i→0}(y) with `jacobian` |∂T_{i→0}/∂y|: its
// stored target over that jacobian where the bridge vouches for it (see Bridge above).
template <class Bridge, class Sample>
RESTIR_HD float own_target(const Bridge& bridge, int i, const Reservoir<Sample>& in, const Sample& x, float jacobian) {
  if constexpr (requires { bridge.stored_target_valid(i); }) {
    if (bridge.stored_target_valid(i)) return in.target / jacobian;
  }
  return bridge.target_from(i, x);
}
}  // namespace detail

// Combines inputs[0] (canonical) with inputs[1..] into a new reservoir in the canonical domain.
// Inputs must be finalized (ucw set) and carry their (possibly capped) confidence. The output's
// confidence is the sum of the inputs' confidences, at most kMaxConfidence; its ucw is set.
template <class Bridge, class Sample>
RESTIR_HD Reservoir<Sample> combine(const Bridge& bridge, std::span<const Reservoir<Sample>* const> inputs, MisWeights weights,
                                    Pcg32& rng, CombineInfo* info = nullptr) {
  const ReuseMis mis = weights.kind;
  Reservoir<Sample> out;
  const int n = int(inputs.size());
  float m_sum = 0;
  for (const auto* r : inputs) m_sum += r->confidence;
  out.confidence = kMaxConfidence < m_sum ? kMaxConfidence : m_sum;  // std::min, by value (device code)
  if (n == 0 || !(m_sum > 0)) return out;
  const float m_c = inputs[0]->confidence, m_rest = m_sum - m_c;
  // A broken canonical reservoir stays broken (its pixel reports it); broken neighbours are skipped.
  if (inputs[0]->non_finite()) out.weight_sum = std::numeric_limits<float>::quiet_NaN();

  for (int i = 0; i < n; ++i) {
    const Reservoir<Sample>& in = *inputs[size_t(i)];
    if (!in.has_sample()) {
      (void)rng.next_float();  // keep the random stream aligned whatever the inputs hold
      continue;
    }
    Sample x = in.sample;
    float jacobian = 1;
    if (i > 0 && !bridge.shift_to_canonical(i, in.sample, x, jacobian)) {
      if (info) ++info->failed_shifts;
      (void)rng.next_float();
      continue;
    }
    const float p0 = i == 0 ? detail::own_target(bridge, 0, in, x, jacobian) : bridge.target_from(0, x);
    float m = 0;
    switch (mis) {
      case ReuseMis::constant:
        m = in.confidence / m_sum;
        break;
      case ReuseMis::one_over_z:
        m = in.confidence;  // 1/Z is applied at finalize
        break;
      case ReuseMis::generalized_balance: {
        float num = 0, den = 0;
        for (int j = 0; j < n; ++j) {
          const float pj = j == 0 ? p0 : j == i ? detail::own_target(bridge, i, in, x, jacobian) : bridge.target_from(j, x);
          const float t = inputs[size_t(j)]->confidence * pj;
          den += t;
          if (j == i) num = t;
        }
        m = den > 0 ? num / den : 0.0f;
        break;
      }
      case ReuseMis::pairwise:
      case ReuseMis::symmetric_ratio:
      case ReuseMis::asymmetric_ratio: {
        if (i == 0) {
          m = detail::pair_canonical_base(weights, m_c, m_sum, m_rest);
          for (int j = 1; j < n; ++j)
            m += detail::pair_canonical_term(weights, inputs[size_t(j)]->confidence, m_sum, m_c, m_rest, p0, bridge.target_from(j, x));
          m = m > 0 ? m : 0.0f;  // asymmetric: 1 − Σ m_j, >= 0 up to rounding
        } else {
          m = detail::pair_neighbor_weight(weights, in.confidence, m_sum, m_c, m_rest, p0, detail::own_target(bridge, i, in, x, jacobian));
        }
        break;
      }
    }
    const float w = resampling_weight(m, p0, in.ucw, jacobian);
    if constexpr (requires { bridge.color(x); }) {
      if (info && info->want_color && w > 0) info->color += color_term(bridge.color(x), w, info->color_input_target ? in.target : p0);
    }
    if (stream(out, x, p0, w, rng.next_float()) && info) info->selected = i;
  }

  float normalization = 1;
  if (mis == ReuseMis::one_over_z && out.target > 0) {
    // Z(Y): confidence of the sources that could have produced Y (Bitterli et al. 2020, Alg. 6).
    float z = 0;
    for (int j = 0; j < n; ++j)
      if ((j == 0 ? out.target : bridge.target_from(j, out.sample)) > 0) z += inputs[size_t(j)]->confidence;
    normalization = z;
  }
  finalize(out, normalization);
  return out;
}

}  // namespace rl::restir
