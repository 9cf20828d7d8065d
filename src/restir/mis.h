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
RESTIR_HD Reservoir<Sample> combine(const Bridge& bridge, std::span<const Reservoir<Sample>* const> inputs, ReuseMis mis, Pcg32& rng,
                          CombineInfo* info = nullptr) {
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
      case ReuseMis::pairwise: {
        if (i == 0) {
          m = m_c / m_sum;
          for (int j = 1; j < n; ++j)
            m += detail::pairwise_canonical_term(inputs[size_t(j)]->confidence, m_sum, m_c, p0, m_rest, bridge.target_from(j, x));
        } else {
          m = detail::pairwise_neighbor_weight(in.confidence, m_sum, m_rest, detail::own_target(bridge, i, in, x, jacobian), m_c, p0);
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
