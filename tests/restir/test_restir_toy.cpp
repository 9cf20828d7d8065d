// The resampling math of src/restir (reservoir.h, mis.h) proved on a 1-D toy domain: integrands on
// [0,1] with known integrals, "domains" with their own target functions and supports, shift
// mappings with non-trivial jacobians, and confidence-interval assertions over thousands of
// independent trials (fixed seeds: deterministic). RESTIR-NOTES.md invariants 1-3.
//
// Every estimator checked here is the GRIS estimator f(Y) · W_Y (Lin et al. 2022, eq. 19-20): its
// mean over independent trials must equal ∫f within 4 standard errors where the math says it is
// unbiased, and differ by more than 6 standard errors where the math says it is biased.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "core/rng.h"
#include "restir/mis.h"
#include "restir/reservoir.h"
#include "stat_utils.h"

using rl::Pcg32;
using namespace rl::restir;

namespace {

using R = Reservoir<float>;

// ---- integrands -------------------------------------------------------------------------------

// f(x) = 1 + sin(3x) on [0,1]; antiderivative x - cos(3x)/3.
double f(double x) { return 1.0 + std::sin(3.0 * x); }
double f_integral(double a, double b) { return (b - std::cos(3.0 * b) / 3.0) - (a - std::cos(3.0 * a) / 3.0); }
const double kIntF = f_integral(0.0, 1.0);  // 1 + (1 - cos 3)/3 ≈ 1.66333

// A raised-cosine bump of half-width h around c: cos²(π(x-c)/(2h)) for |x-c| < h; ∫ = h.
double bump(double c, double h, double x) {
  const double d = (x - c) / h;
  if (!(std::fabs(d) < 1)) return 0.0;
  const double v = std::cos(0.5 * M_PI * d);
  return v * v;
}

// ---- statistics -------------------------------------------------------------------------------

struct Acc {
  double s = 0, s2 = 0;
  long n = 0;
  void add(double v) { s += v; s2 += v * v; ++n; }
  double mean() const { return n ? s / double(n) : 0.0; }
  double var() const { return n > 1 ? std::max(0.0, s2 / double(n) - mean() * mean()) * double(n) / double(n - 1) : 0.0; }
  double se() const { return n > 1 ? std::sqrt(var() / double(n)) : 0.0; }
};

// |mean - ref| <= k SE; a zero-variance estimator must hit ref to float precision.
bool within(const Acc& a, double ref, double k = 4.0) {
  return a.n > 1 && std::fabs(a.mean() - ref) <= std::max(k * a.se(), 1e-6 * std::fabs(ref));
}

void check_unbiased(const Acc& a, double ref, const std::string& what) {
  INFO(what << ": mean " << a.mean() << ", expected " << ref << ", se " << a.se() << ", |z| = "
            << std::fabs(a.mean() - ref) / a.se());
  CHECK(within(a, ref));
}

// ---- source pdfs and streaming RIS --------------------------------------------------------------

enum class Src { uniform, linear };  // p(x) = 1, p(x) = 0.5 + x on [0,1]
double src_sample(Src s, double u) { return s == Src::uniform ? u : 0.5 * (-1.0 + std::sqrt(1.0 + 8.0 * u)); }
double src_pdf(Src s, double x) { return s == Src::uniform ? 1.0 : 0.5 + x; }

// A fresh reservoir: K candidates from the source, w = (1/K) p̂(x)/p(x), confidence K, finalized.
template <class Target>
R ris(const Target& target, int K, Src s, Pcg32& rng) {
  R r;
  for (int k = 0; k < K; ++k) {
    const float y = float(src_sample(s, rng.next_float()));
    const double t = target(double(y));
    stream(r, y, float(t), float(t / (src_pdf(s, double(y)) * K)), rng.next_float());
  }
  r.confidence = float(K);
  finalize(r);
  return r;
}

template <class Integrand>
double estimate(const R& r, const Integrand& integrand) { return r.has_sample() ? integrand(double(r.sample)) * double(r.ucw) : 0.0; }

// ---- toy domains and bridges --------------------------------------------------------------------

// Domain i's target in canonical coordinates is shape(x) on [lo, hi] ∩ [0,1]. With the shifted
// bridge domain i lives in its own coordinate y ∈ [0,1], mapped to the canonical x ∈ [lo, hi] by
// x = lo + (hi - lo) · w⁻¹(y), w(u) = (e^{cu} - 1)/(e^c - 1) (c = 0: w(u) = u): a non-linear,
// invertible warp onto a sub-interval. Where that map leaves [0,1] (hi > 1) the shift fails.
struct ToyDomain {
  double lo = 0, hi = 1, c = 0;
  int shape = 0;
};

double shape_fn(int s, double x) {
  switch (s) {
    case 0: return f(x);
    case 1: return f(x) * (0.3 + 2.0 * x);
    case 2: return 1.0 + 4.0 * x;
    case 3: return f(x) * std::exp(-3.0 * x);
    default: return 0.0;
  }
}

double warp_d(double c, double u) { return c == 0 ? 1.0 : c * std::exp(c * u) / std::expm1(c); }
double warp_inv(double c, double y) { return c == 0 ? y : std::log1p(y * std::expm1(c)) / c; }
double warp_inv_d(double c, double y) { return c == 0 ? 1.0 : std::expm1(c) / (c * (1.0 + y * std::expm1(c))); }

// The bridge of mis.h over a set of toy domains (0 = canonical, whose map is the identity).
struct ToyBridge {
  std::span<const ToyDomain> dom;
  bool shifted = false;

  double to_canonical(int i, double y) const { const auto& d = dom[size_t(i)]; return d.lo + (d.hi - d.lo) * warp_inv(d.c, y); }
  // |dx/dy| of the shift y -> x (domain i to canonical).
  double jac_to_canonical(int i, double y) const { const auto& d = dom[size_t(i)]; return (d.hi - d.lo) * warp_inv_d(d.c, y); }
  // |dy/dx| of the inverse shift x -> y (canonical to domain i).
  double jac_from_canonical(int i, double x) const {
    const auto& d = dom[size_t(i)];
    return warp_d(d.c, (x - d.lo) / (d.hi - d.lo)) / (d.hi - d.lo);
  }

  // Domain i's target function in its own coordinates (what its initial reservoir resamples).
  double own_target(int i, double y) const {
    if (!shifted) return canonical_target(i, y);
    if (y < 0 || y > 1) return 0.0;
    return shape_fn(dom[size_t(i)].shape, to_canonical(i, y));
  }
  // p̂_{←i}(x): domain i's target at the canonical x shifted back, times |dy/dx|.
  double canonical_target(int i, double x) const {
    const auto& d = dom[size_t(i)];
    if (x < 0 || x > 1 || x < d.lo || x > d.hi) return 0.0;
    const double t = shape_fn(d.shape, x);
    return shifted && i > 0 ? t * jac_from_canonical(i, x) : t;
  }

  bool shift_to_canonical(int i, const float& y, float& x, float& jacobian) const {
    if (!shifted) {
      x = y;
      jacobian = 1;
      return true;
    }
    const double xd = to_canonical(i, double(y));
    if (xd < 0 || xd > 1) return false;
    x = float(xd);
    jacobian = float(jac_to_canonical(i, double(y)));
    return true;
  }
  float target_from(int i, const float& x) const { return float(canonical_target(i, double(x))); }
};

// Canonical [0,1] with p̂_0 = f, and four neighbours with different targets AND supports: [0, 0.1)
// is covered by the canonical and domain 2 only, (0.45, 0.6) by 0, 1, 3; domain 4 maps partly
// outside [0,1] (its shift fails there).
constexpr std::array<ToyDomain, 5> kDomains{{
    {0.0, 1.0, 0.0, 0},
    {0.1, 1.0, 1.5, 1},
    {0.0, 0.45, -2.0, 0},
    {0.3, 0.8, 0.7, 2},
    {0.6, 1.2, 2.5, 3},
}};

// ∫f over the canonical part of domain i's support.
double covered_integral(const ToyDomain& d) { return f_integral(std::max(0.0, d.lo), std::min(1.0, d.hi)); }

const char* mis_name(ReuseMis m) {
  switch (m) {
    case ReuseMis::constant: return "constant";
    case ReuseMis::one_over_z: return "one_over_z";
    case ReuseMis::generalized_balance: return "generalized_balance";
    case ReuseMis::pairwise: return "pairwise";
    case ReuseMis::symmetric_ratio: return "symmetric_ratio";
    case ReuseMis::asymmetric_ratio: return "asymmetric_ratio";
  }
  return "?";
}

constexpr std::array<ReuseMis, 5> kUnbiasedModes{ReuseMis::one_over_z, ReuseMis::generalized_balance, ReuseMis::pairwise,
                                                  ReuseMis::symmetric_ratio, ReuseMis::asymmetric_ratio};

// One spatial-reuse trial: a fresh reservoir per domain (K candidates; domain 1 optionally a
// "temporal-like" input of 40 K candidates whose confidence is capped to 20 K), combined.
R spatial_trial(const ToyBridge& bridge, MisWeights mis, int K, bool unequal, Pcg32& rng, CombineInfo* info = nullptr) {
  const int n = int(bridge.dom.size());
  std::array<R, 8> res;
  std::array<const R*, 8> ptr{};
  for (int i = 0; i < n; ++i) {
    const int k = unequal && i == 1 ? 40 * K : K;
    const Src s = i == 0 ? Src::linear : Src::uniform;
    res[size_t(i)] = ris([&](double y) { return bridge.own_target(i, y); }, k, s, rng);
    if (unequal && i == 1) res[1].confidence = capped_confidence(res[1].confidence, float(K), 20.0f);
    ptr[size_t(i)] = &res[size_t(i)];
  }
  return combine(bridge, std::span<const R* const>(ptr.data(), size_t(n)), mis, rng, info);
}

}  // namespace

TEST_SUITE("restir_toy") {

// Invariant 1 for a single source: streaming RIS (Talbot 2005; Bitterli et al. 2020, Alg. 2-3).
TEST_CASE("restir_toy: streaming RIS from one source is unbiased, W is an unbiased contribution weight") {
  constexpr int kTrials = 20000;
  const auto target = [](double x) { return 0.3 + x; };  // a rough target, not proportional to f
  const auto narrow = [](double x) { return x >= 0.2 && x < 0.7 ? f(x) : 0.0; };  // support [0.2, 0.7)
  for (Src s : {Src::uniform, Src::linear}) {
    for (int K : {1, 4, 32}) {
      CAPTURE(K);
      CAPTURE(int(s));
      Pcg32 rng(1000 + uint64_t(K), uint64_t(s) + 1);
      Acc est, w, wp, bins[4], est_narrow, w_narrow;
      bool k1_is_importance_sampling = true, all_sampled = true, confidence_ok = true;
      for (int t = 0; t < kTrials; ++t) {
        const R r = ris(target, K, s, rng);
        all_sampled = all_sampled && r.has_sample();  // p̂ > 0 everywhere: every reservoir holds a sample
        confidence_ok = confidence_ok && r.confidence == float(K);
        const double y = r.sample, W = r.ucw;
        est.add(f(y) * W);
        w.add(W);
        wp.add(W * target(y));
        for (int b = 0; b < 4; ++b) bins[b].add(y >= 0.25 * b && y < 0.25 * (b + 1) ? W : 0.0);
        // One candidate: RIS is plain importance sampling, W = 1/p(Y).
        if (K == 1 && std::fabs(W * src_pdf(s, y) - 1.0) > 1e-5) k1_is_importance_sampling = false;
        const R rn = ris(narrow, K, s, rng);
        est_narrow.add(estimate(rn, f));
        w_narrow.add(rn.ucw);
      }
      check_unbiased(est, kIntF, "E[f(Y) W] = ∫f");
      check_unbiased(w, 1.0, "E[W] = |support| = 1");
      check_unbiased(wp, 0.8, "E[W p̂(Y)] = ∫p̂ = 0.8");
      // W as a measure: E[1_B(Y) W] = |B| on every bin (the distribution of Y times W is Lebesgue).
      for (int b = 0; b < 4; ++b) check_unbiased(bins[b], 0.25, "E[1_B(Y) W] = |B|, bin " + std::to_string(b));
      // Where p̂ = 0 the estimator sees nothing: with p̂ supported on [0.2, 0.7) it integrates f there only.
      check_unbiased(est_narrow, f_integral(0.2, 0.7), "narrow target: E[f(Y) W] = ∫_{0.2}^{0.7} f");
      check_unbiased(w_narrow, 0.5, "narrow target: E[W] = 0.5");
      CHECK(all_sampled);
      CHECK(confidence_ok);
      if (K == 1) CHECK(k1_is_importance_sampling);
    }
  }
  // With p̂ = f more candidates approach perfect importance sampling: the variance must drop.
  Pcg32 rng(77, 3);
  Acc v1, v32;
  for (int t = 0; t < 4000; ++t) {
    v1.add(estimate(ris(f, 1, Src::uniform, rng), f));
    v32.add(estimate(ris(f, 32, Src::uniform, rng), f));
  }
  INFO("Var K=1 " << v1.var() << ", Var K=32 " << v32.var());
  CHECK(v32.var() < 0.1 * v1.var());
}

// Invariant 1 + 2: reuse across domains with different targets and supports, identity and shifted.
TEST_CASE("restir_toy: combine() is unbiased for 1/Z, generalized balance, pairwise and the ratio MIS weights") {
  constexpr int kTrials = 20000, K = 4;
  for (bool shifted : {false, true}) {
    const ToyBridge bridge{kDomains, shifted};
    for (bool unequal : {false, true}) {
      for (ReuseMis mis : kUnbiasedModes) {
        const std::string what = std::string(mis_name(mis)) + (shifted ? ", shifted bridge" : ", identity bridge") +
                                 (unequal ? ", confidences K,20K,K,K,K" : ", equal confidences");
        Pcg32 rng(2000 + uint64_t(mis) * 10 + uint64_t(shifted) * 2 + uint64_t(unequal), 5);
        Acc est;
        int failed = 0;
        std::array<int, 5> selected{};
        float confidence = 0;
        for (int t = 0; t < kTrials; ++t) {
          CombineInfo info;
          const R r = spatial_trial(bridge, mis, K, unequal, rng, &info);
          est.add(estimate(r, f));
          failed += info.failed_shifts;
          if (info.selected >= 0) ++selected[size_t(info.selected)];
          confidence = r.confidence;
        }
        check_unbiased(est, kIntF, what);
        INFO(what);
        CHECK(confidence == float(unequal ? 24 * K : 5 * K));  // the output's M is the sum of the inputs'
        for (int i = 0; i < 5; ++i) CHECK(selected[size_t(i)] > 0);  // every input is reused
        CHECK((failed > 0) == shifted);  // domain 4's shift leaves [0,1] part of the time
      }
    }
  }
}

// The pairwise family's weights (mis.h) sum to one over the techniques at every sample, for any
// targets, confidences and ratio exponent -- the GRIS condition (Lin et al. 2022, eq. 19) -- and
// vanish where a neighbour's target does: m_c(x) + Σ_j m_j(x) = 1 with p0 = p̂_0(x) > 0 and
// pj = p̂_{←j}(x) >= 0, m_j computed as for neighbour j's own sample at x.
TEST_CASE("restir_toy: the pairwise family's MIS weights sum to one at every sample, for any targets and confidences") {
  Pcg32 rng(4242, 7);
  double worst = 0;
  int checked = 0;
  bool zero_ok = true, nonnegative = true;
  for (ReuseMis kind : {ReuseMis::pairwise, ReuseMis::symmetric_ratio, ReuseMis::asymmetric_ratio}) {
    for (float beta : {0.5f, 1.0f, 2.0f, 5.0f}) {
      const MisWeights w(kind, beta);
      for (int t = 0; t < 5000; ++t) {
        const int n = 2 + int(rng.next_float() * 6.0f);
        float conf[8], pj[8];
        float m_sum = 0;
        for (int j = 0; j < n; ++j) {
          conf[j] = t % 7 == 0 && j > 0 ? 0.0f : 1.0f + std::floor(rng.next_float() * 20.0f);
          // Targets over four decades, and some zeros (a domain that cannot produce x).
          pj[j] = rng.next_float() < 0.15f && j > 0 ? 0.0f : std::pow(10.0f, 4.0f * rng.next_float() - 2.0f);
          m_sum += conf[j];
        }
        const float m_c = conf[0], m_rest = m_sum - m_c, p0 = pj[0];
        double sum = detail::pair_canonical_base(w, m_c, m_sum, m_rest);
        for (int j = 1; j < n; ++j) sum += detail::pair_canonical_term(w, conf[j], m_sum, m_c, m_rest, p0, pj[j]);
        nonnegative = nonnegative && sum >= -1e-6;
        for (int j = 1; j < n; ++j) {
          const float mj = detail::pair_neighbor_weight(w, conf[j], m_sum, m_c, m_rest, p0, pj[j]);
          nonnegative = nonnegative && mj >= 0;
          if (pj[j] == 0 && mj != 0) zero_ok = false;
          sum += mj;
        }
        worst = std::max(worst, std::fabs(sum - 1.0));
        ++checked;
      }
    }
  }
  MESSAGE(checked << " weight sets, worst |Σ m - 1| = " << worst);
  CHECK(worst < 1e-5);
  CHECK(zero_ok);
  CHECK(nonnegative);
  // The planted mismatch (asymmetric neighbours, symmetric canonical) does not sum to one.
  const MisWeights planted(ReuseMis::asymmetric_ratio, 2, true);
  const float conf[3] = {4, 4, 4}, p[3] = {1.0f, 3.0f, 0.5f};
  double sum = detail::pair_canonical_base(planted, 4, 12, 8);
  for (int j = 1; j < 3; ++j) sum += detail::pair_canonical_term(planted, conf[j], 12, 4, 8, p[0], p[j]);
  for (int j = 1; j < 3; ++j) sum += detail::pair_neighbor_weight(planted, conf[j], 12, 4, 8, p[0], p[j]);
  CHECK(std::fabs(sum - 1.0) > 0.05);
}

// The harness above has the power to see a ratio weight that does not sum to one: asymmetric
// ratio weights with the symmetric formula's canonical weight (PlantedBias::ratio_canonical_symmetric).
TEST_CASE("restir_toy: asymmetric ratio weights with a mismatched canonical weight are biased, and the toy sees it") {
  constexpr int kTrials = 20000, K = 4;
  const ToyBridge bridge{kDomains, true};
  Pcg32 rng(9090, 5);
  Acc est;
  for (int t = 0; t < kTrials; ++t) est.add(estimate(spatial_trial(bridge, MisWeights(ReuseMis::asymmetric_ratio, 2, true), K, false, rng), f));
  const double z = std::fabs(est.mean() - kIntF) / est.se();
  MESSAGE("planted mismatch: mean " << est.mean() << " vs " << kIntF << ", " << z << " se");
  CHECK(z > 6);
}

// A bridge over the unshifted toy that counts its target evaluations and, with Vouch, tells
// combine() that each input's stored target is its own p̂_{←i} (mis.h: stored_target_valid).
template <bool Vouch>
struct CountingBridge {
  ToyBridge toy;
  mutable long evaluations = 0;
  bool shift_to_canonical(int i, const float& y, float& x, float& jacobian) const { return toy.shift_to_canonical(i, y, x, jacobian); }
  float target_from(int i, const float& x) const {
    ++evaluations;
    return toy.target_from(i, x);
  }
  bool stored_target_valid(int) const requires Vouch { return true; }
};

// Reading a stored target is an optimisation, not an approximation: with the identity shift the
// output reservoir is bit for bit the one of evaluating every target, with fewer evaluations; and
// a stored target that is wrong does change the result (the stored value is really what is read).
TEST_CASE("restir_toy: combine() reads vouched stored targets: same reservoirs, fewer evaluations") {
  constexpr int kTrials = 2000, K = 4;
  for (ReuseMis mis : {ReuseMis::one_over_z, ReuseMis::generalized_balance, ReuseMis::pairwise}) {
    CAPTURE(mis_name(mis));
    const ToyBridge toy{kDomains, false};
    CountingBridge<false> plain{toy};
    CountingBridge<true> vouched{toy}, vouched_wrong{toy};
    Pcg32 rng(4242, 9);
    int identical = 0, differ_when_wrong = 0;
    for (int t = 0; t < kTrials; ++t) {
      std::array<R, 5> res, wrong;
      std::array<const R*, 5> ptr{}, wrong_ptr{};
      for (int i = 0; i < 5; ++i) {
        res[size_t(i)] = ris([&](double y) { return toy.own_target(i, y); }, K, i == 0 ? Src::linear : Src::uniform, rng);
        wrong[size_t(i)] = res[size_t(i)];
        wrong[size_t(i)].target *= 1.5f;  // a stored target that is not p̂_i of the sample
        ptr[size_t(i)] = &res[size_t(i)];
        wrong_ptr[size_t(i)] = &wrong[size_t(i)];
      }
      const uint64_t state = rng.next_u32();
      Pcg32 a(state, 1), b(state, 1), c(state, 1);
      const R ra = combine(plain, std::span<const R* const>(ptr.data(), 5), mis, a);
      const R rb = combine(vouched, std::span<const R* const>(ptr.data(), 5), mis, b);
      const R rc = combine(vouched_wrong, std::span<const R* const>(wrong_ptr.data(), 5), mis, c);
      identical += ra.sample == rb.sample && ra.ucw == rb.ucw && ra.target == rb.target && ra.weight_sum == rb.weight_sum;
      differ_when_wrong += rc.ucw != ra.ucw || rc.sample != ra.sample;
    }
    CHECK(identical == kTrials);
    CHECK(vouched.evaluations < plain.evaluations);
    CHECK(differ_when_wrong > kTrials / 2);
    const std::string note = std::string(mis_name(mis)) + ": target evaluations " + std::to_string(plain.evaluations) +
                             " -> " + std::to_string(vouched.evaluations);
    MESSAGE(note);
  }
}

// Saturated confidences: the sum is held at kMaxConfidence and the weights stay what they would be
// at the same ratios (the estimator only sees ratios of confidences).
TEST_CASE("restir_toy: combine() saturates the confidence at kMaxConfidence with finite, unchanged weights") {
  const ToyBridge toy{kDomains, false};
  for (ReuseMis mis : kUnbiasedModes) {
    CAPTURE(mis_name(mis));
    Pcg32 rng(99, 1);
    for (int t = 0; t < 200; ++t) {
      std::array<R, 5> big, small;
      std::array<const R*, 5> pb{}, ps{};
      for (int i = 0; i < 5; ++i) {
        small[size_t(i)] = ris([&](double y) { return toy.own_target(i, y); }, 4, Src::uniform, rng);
        big[size_t(i)] = small[size_t(i)];
        big[size_t(i)].confidence = kMaxConfidence * (i == 0 ? 1e-18f : 1.0f);  // an enormous history
        small[size_t(i)].confidence = i == 0 ? 1e-18f : 1.0f;                  // the same ratios
        pb[size_t(i)] = &big[size_t(i)];
        ps[size_t(i)] = &small[size_t(i)];
      }
      const uint64_t state = rng.next_u32();
      Pcg32 a(state, 1), b(state, 1);
      const R rb = combine(toy, std::span<const R* const>(pb.data(), 5), mis, a);
      const R rs = combine(toy, std::span<const R* const>(ps.data(), 5), mis, b);
      REQUIRE(rb.confidence == kMaxConfidence);
      REQUIRE(std::isfinite(rb.ucw));
      REQUIRE(rb.sample == rs.sample);
      REQUIRE(rb.ucw == doctest::Approx(rs.ucw).epsilon(1e-4));
    }
  }
}

// Invariant 2: constant MIS (m_i = M_i/ΣM) is biased exactly as the math predicts when supports
// differ, and unbiased when all inputs cover the canonical support.
TEST_CASE("restir_toy: constant MIS is biased with different supports, unbiased with equal ones") {
  constexpr int kTrials = 20000, K = 4;
  for (bool shifted : {false, true}) {
    for (bool unequal : {false, true}) {
      const ToyBridge bridge{kDomains, shifted};
      Pcg32 rng(3000 + uint64_t(shifted) * 2 + uint64_t(unequal), 9);
      Acc est;
      for (int t = 0; t < kTrials; ++t) est.add(estimate(spatial_trial(bridge, ReuseMis::constant, K, unequal, rng), f));
      // E = Σ_i (M_i/ΣM) ∫_{supp_i} f: each input's W is unbiased over its own support only.
      double predicted = 0, m_sum = 0;
      for (size_t i = 0; i < kDomains.size(); ++i) {
        const double m = unequal && i == 1 ? 20.0 : 1.0;
        predicted += m * covered_integral(kDomains[i]);
        m_sum += m;
      }
      predicted /= m_sum;
      INFO(std::string(shifted ? "shifted" : "identity") << std::string(unequal ? ", unequal M" : ", equal M") << ": mean " << est.mean()
                                              << ", ∫f " << kIntF << ", predicted " << predicted << ", se " << est.se());
      CHECK(std::fabs(est.mean() - kIntF) > 6 * est.se());  // the bias exists
      CHECK(within(est, predicted));                        // and is the predicted one
    }
  }
  // Equal supports: identical domains, and full-support domains with different targets and warps.
  const std::array<ToyDomain, 4> identical{{{0, 1, 0, 0}, {0, 1, 0, 0}, {0, 1, 0, 0}, {0, 1, 0, 0}}};
  const std::array<ToyDomain, 4> full{{{0, 1, 0, 0}, {0, 1, 1.5, 1}, {0, 1, -2.0, 2}, {0, 1, 0.7, 3}}};
  int seed = 0;
  for (auto doms : {std::span<const ToyDomain>(identical), std::span<const ToyDomain>(full)}) {
    for (bool shifted : {false, true}) {
      for (bool unequal : {false, true}) {
        const ToyBridge bridge{doms, shifted};
        Pcg32 rng(3100 + uint64_t(seed++), 9);
        Acc est;
        for (int t = 0; t < kTrials; ++t) est.add(estimate(spatial_trial(bridge, ReuseMis::constant, K, unequal, rng), f));
        check_unbiased(est, kIntF, std::string("constant MIS, equal supports") + (doms.data() == identical.data() ? " (identical)" : " (different targets)") +
                                       (shifted ? ", shifted" : ", identity") + (unequal ? ", unequal M" : ""));
      }
    }
  }
}

// Chained (temporal) reuse: each frame combines a fresh canonical reservoir with the previous
// frame's output (confidence capped or not), optionally plus a fresh neighbour with a smaller support.
TEST_CASE("restir_toy: chained temporal reuse stays unbiased; the M-cap bounds the confidence") {
  constexpr int kTrials = 3000, kFrames = 30, K = 4;
  constexpr float kCap = 20;
  const std::array<ToyDomain, 3> doms{{{0, 1, 0, 0}, {0, 1, 0, 0}, {0.0, 0.45, 0, 0}}};  // canonical, history, neighbour
  const ToyBridge bridge{doms, false};
  for (ReuseMis mis : kUnbiasedModes) {
    for (bool capped : {true, false}) {
      for (bool neighbour : {false, true}) {
        const std::string what = std::string(mis_name(mis)) + (capped ? ", cap 20" : ", no cap") + (neighbour ? ", + neighbour" : "");
        Pcg32 rng(4000 + uint64_t(mis) * 4 + uint64_t(capped) * 2 + uint64_t(neighbour), 11);
        std::vector<Acc> est(kFrames);
        float max_conf = 0, last_conf = 0;
        bool conf_exact = true;
        for (int t = 0; t < kTrials; ++t) {
          R prev;  // empty before frame 0 (confidence 0)
          for (int frame = 0; frame < kFrames; ++frame) {
            R canonical = ris(f, K, Src::uniform, rng);
            R history = prev;
            history.confidence = capped_confidence(prev.confidence, canonical.confidence, capped ? kCap : 0.0f);
            R nb = ris([&](double x) { return bridge.own_target(2, x); }, K, Src::uniform, rng);
            const std::array<const R*, 3> in{&canonical, &history, &nb};
            prev = combine(bridge, std::span<const R* const>(in.data(), neighbour ? 3 : 2), mis, rng);
            est[size_t(frame)].add(estimate(prev, f));
            max_conf = std::max(max_conf, prev.confidence);
            if (!capped && prev.confidence != float((frame + 1) * K * (neighbour ? 2 : 1))) conf_exact = false;
          }
          last_conf = prev.confidence;
        }
        for (int frame = 0; frame < kFrames; ++frame) check_unbiased(est[size_t(frame)], kIntF, what + ", frame " + std::to_string(frame));
        INFO(what << ": max confidence " << max_conf << ", last " << last_conf);
        const float k_new = float(K * (neighbour ? 2 : 1));  // confidence of the fresh inputs per frame
        if (capped) {
          CHECK(max_conf <= kCap * K + k_new);  // (cap + 1) K without the neighbour
          CHECK(last_conf == kCap * K + k_new);  // and the cap is reached
        } else {
          CHECK(conf_exact);  // (frame + 1) · fresh confidence: grows without bound
          CHECK(last_conf == float(kFrames) * k_new);
          CHECK(last_conf > kCap * K + k_new);  // past what the cap allows
        }
      }
    }
  }
}

// Invariant 3 (thesis §4.2.4): a dynamic toy. The integrand is a "light" on [c - 0.3, c + 0.3)
// (a plateau 0.5 plus a bump) around c = 0.3 for the first t0 frames, which then jumps to c = 0.65.
// The history's samples were built for the old light, but the renderer evaluates the history's
// target with the current scene ("as if current"), so the part of the new light the history never
// covers is under-weighted. With the M-cap the new samples keep a weight of about 1/21 and the error
// decays like (20/21)^n; without it the history's weight keeps growing and the error decays like
// t0/(t0 + n). Evaluating the history's target with the previous scene (RESTIR-NOTES pitfall) is
// unbiased at once. (The plateau keeps f_new/f_old bounded where both are non-zero, so the stale
// history's estimates have a finite variance and the standard errors mean something.)
namespace {
double light(double c, double x) { return std::fabs(x - c) < 0.3 ? 0.5 + bump(c, 0.3, x) : 0.0; }  // ∫ = 0.6
struct DynBridge {
  double c_now, c_hist;
  bool shift_to_canonical(int, const float& y, float& x, float& j) const { x = y; j = 1; return true; }
  float target_from(int i, const float& x) const { return float(light(i == 0 ? c_now : c_hist, double(x))); }
};
enum class Hist { capped, uncapped, previous_target };
}  // namespace

TEST_CASE("restir_toy: M-cap lets a dynamic toy recover; without it the stale history dominates") {
  constexpr int kTrials = 3000, kT0 = 40, kAfter = 60, K = 4;
  constexpr double kOld = 0.3, kNew = 0.65, kIntNew = 0.6;
  for (ReuseMis mis : {ReuseMis::constant, ReuseMis::one_over_z, ReuseMis::generalized_balance, ReuseMis::pairwise}) {
    std::array<std::vector<Acc>, 3> est;
    for (Hist h : {Hist::capped, Hist::uncapped, Hist::previous_target}) {
      auto& e = est[size_t(h)];
      e.assign(size_t(kAfter), Acc{});
      Pcg32 rng(5000 + uint64_t(mis) * 3 + uint64_t(h), 13);
      for (int t = 0; t < kTrials; ++t) {
        R prev;
        double prev_centre = kOld;
        for (int frame = 0; frame < kT0 + kAfter; ++frame) {
          const double centre = frame < kT0 ? kOld : kNew;
          const auto f_dyn = [centre](double x) { return light(centre, x); };
          R canonical = ris(f_dyn, K, Src::uniform, rng);
          R history = prev;
          history.confidence = capped_confidence(prev.confidence, canonical.confidence, h == Hist::uncapped ? 0.0f : 20.0f);
          const DynBridge bridge{centre, h == Hist::previous_target ? prev_centre : centre};
          const std::array<const R*, 2> in{&canonical, &history};
          prev = combine(bridge, std::span<const R* const>(in.data(), in.size()), mis, rng);
          prev_centre = centre;
          if (frame >= kT0) e[size_t(frame - kT0)].add(estimate(prev, f_dyn));
        }
      }
    }
    const auto rel = [&](Hist h, int n) { return std::fabs(est[size_t(h)][size_t(n)].mean() - kIntNew) / kIntNew; };
    const auto& cap = est[size_t(Hist::capped)][kAfter - 1];
    const auto& unc = est[size_t(Hist::uncapped)][kAfter - 1];
    INFO(std::string(mis_name(mis)) << ": relative error at frame t0: capped " << rel(Hist::capped, 0) << ", uncapped "
                       << rel(Hist::uncapped, 0) << "; after " << kAfter << " frames: capped " << rel(Hist::capped, kAfter - 1)
                       << " (se " << cap.se() / kIntNew << "), uncapped " << rel(Hist::uncapped, kAfter - 1) << " (se "
                       << unc.se() / kIntNew << ")");
    // Right after the change both are wrong (the history claims the new light's support).
    CHECK(rel(Hist::capped, 0) > 0.2);
    CHECK(rel(Hist::uncapped, 0) > 0.2);
    // Capped: within a few percent after 60 frames.
    CHECK(rel(Hist::capped, kAfter - 1) < 0.05);
    // Uncapped: still clearly wrong, by more than 6 combined standard errors and twice the capped error.
    const double diff = std::fabs(unc.mean() - kIntNew) - std::fabs(cap.mean() - kIntNew);
    CHECK(diff > 6 * std::hypot(cap.se(), unc.se()));
    CHECK(rel(Hist::uncapped, kAfter - 1) > 2 * rel(Hist::capped, kAfter - 1));
    // The history's target evaluated in the previous scene: unbiased from the first changed frame
    // (unbiased modes only; constant MIS is biased by the changed support).
    if (mis != ReuseMis::constant)
      for (int n : {0, 1, 5, kAfter - 1})
        check_unbiased(est[size_t(Hist::previous_target)][size_t(n)], kIntNew,
                       std::string(mis_name(mis)) + ", previous-frame target, frame t0+" + std::to_string(n));
  }
}

}  // TEST_SUITE
