// The reservoir primitive of src/restir (reservoir.h): stream() selects each candidate with
// probability w_i / sum w (chi-square over 100 000 trials), skips invalid weights, and leaves a
// broken integrand (NaN weight, non-finite target) visible. The estimators built on it are proved
// in test_restir_toy.cpp.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "core/rng.h"
#include "restir/reservoir.h"
#include "stat_utils.h"

using rl::Pcg32;
using namespace rl::restir;

namespace {
using R = Reservoir<float>;
}  // namespace

TEST_SUITE("restir_toy") {

// Weighted reservoir sampling (Chao 1982): stream() keeps candidate i with probability w_i/Σw.
TEST_CASE("restir_toy: stream() selects candidates with probability w_i / sum w; invalid weights never") {
  constexpr int kTrials = 100000;
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  // Zero, negative and infinite weights are skipped; NaN is not (below: it makes the reservoir
  // non-finite, for the render driver to report).
  const std::vector<float> weights{1.0f, 0.0f, 3.0f, 0.5f, -2.0f, 2.0f, inf, 0.01f, 4.0f, -0.0f, 0.25f};
  double valid_sum = 0;
  float valid_sum_f = 0;
  for (float w : weights)
    if (w > 0 && std::isfinite(w)) { valid_sum += w; valid_sum_f += w; }
  for (bool reversed : {false, true}) {
    CAPTURE(reversed);
    std::vector<double> count(weights.size(), 0.0);
    Pcg32 rng(6000 + uint64_t(reversed), 17);
    bool sums_ok = true, returns_ok = true;
    for (int t = 0; t < kTrials; ++t) {
      R r;
      int chosen = -1;
      for (size_t k = 0; k < weights.size(); ++k) {
        const size_t i = reversed ? weights.size() - 1 - k : k;
        const bool valid = weights[i] > 0 && std::isfinite(weights[i]);
        const bool replaced = stream(r, float(i), 1.0f, weights[i], rng.next_float());
        if (replaced) chosen = int(i);
        if (replaced && !valid) returns_ok = false;
      }
      if (chosen >= 0) count[size_t(chosen)] += 1;
      if (std::fabs(r.weight_sum - valid_sum_f) > 1e-5f * valid_sum_f) sums_ok = false;
      if (chosen < 0 || r.sample != float(chosen)) returns_ok = false;
    }
    CHECK(sums_ok);     // weight_sum is the sum of the valid weights only
    CHECK(returns_ok);  // stream() returns true exactly when it replaced the sample
    std::vector<double> expected(weights.size(), 0.0);
    for (size_t i = 0; i < weights.size(); ++i) {
      const bool valid = weights[i] > 0 && std::isfinite(weights[i]);
      if (!valid) {
        INFO("invalid weight " << weights[i] << " at " << i);
        CHECK(count[i] == 0);
        continue;
      }
      const double p = weights[i] / valid_sum;
      expected[i] = p * kTrials;
      // Per-bin binomial bound, 5 sigma.
      INFO("candidate " << i << ": " << count[i] << " vs " << expected[i]);
      CHECK(std::fabs(count[i] - expected[i]) <= 5 * std::sqrt(kTrials * p * (1 - p)));
    }
    const auto chi2 = rl::stat::chi2_test(count, expected);
    INFO(rl::stat::describe(chi2));
    CHECK(chi2.message.empty());
    CHECK(chi2.p > 1e-3);
  }
  // No valid candidate: no sample, W = 0.
  R empty;
  for (float w : {0.0f, -1.0f, inf}) CHECK_FALSE(stream(empty, 1.0f, 1.0f, w, 0.5f));
  finalize(empty);
  CHECK_FALSE(empty.has_sample());
  CHECK_FALSE(empty.non_finite());
  CHECK(empty.ucw == 0.0f);
  // A NaN weight or a non-finite target is a broken integrand: never selected, never hidden.
  for (auto [target, w] : {std::pair{1.0f, nan}, std::pair{nan, 1.0f}, std::pair{inf, 1.0f}}) {
    R broken;
    CHECK(stream(broken, 1.0f, 1.0f, 2.0f, 0.5f));
    CHECK_FALSE(stream(broken, 2.0f, target, w, 0.0f));
    CHECK(stream(broken, 3.0f, 1.0f, 2.0f, 0.0f) == false);
    finalize(broken);
    CHECK(broken.non_finite());
    CHECK_FALSE(broken.has_sample());
  }
  CHECK(resampling_weight(0.0f, 1.0f, 1.0f, inf) == 0.0f);   // no sample, whatever the jacobian
  CHECK(std::isnan(resampling_weight(0.5f, nan, 1.0f, 1.0f)));
  CHECK(resampling_weight(0.5f, 1.0f, 1.0f, inf) == 0.0f);   // degenerate shift: dropped
}

}  // TEST_SUITE
