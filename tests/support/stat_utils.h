// Statistical helpers for the sampling tests: Pearson's chi-square goodness-of-fit test with
// pooling of low-expected cells, and a (theta, phi) grid over the sphere of directions whose
// expected counts come from integrating a pdf over each cell (pbrt-v3's chi2 test,
// src/tests/bsdfs.cpp; Mitsuba's ChiSquareTest). p-values use the regularized upper incomplete
// gamma function Q(dof/2, chi2/2) (Numerical Recipes 3rd ed., sec. 6.2).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "core/math.h"
#include "core/rng.h"

namespace rl::stat {

// Regularized lower incomplete gamma P(a, x) by its series, upper Q(a, x) by Lentz's continued
// fraction (NR3 eqs. 6.2.5 and 6.2.7); each used where it converges fast.
inline double gamma_q(double a, double x) {
  if (!(x > 0)) return 1.0;
  const double gln = std::lgamma(a);
  if (x < a + 1) {
    double ap = a, sum = 1.0 / a, del = sum;
    for (int n = 0; n < 10000; ++n) {
      ap += 1;
      del *= x / ap;
      sum += del;
      if (std::fabs(del) < std::fabs(sum) * 1e-15) break;
    }
    return std::max(0.0, 1.0 - sum * std::exp(-x + a * std::log(x) - gln));
  }
  const double fpmin = 1e-300;
  double b = x + 1 - a, c = 1 / fpmin, d = 1 / b, h = d;
  for (int i = 1; i < 10000; ++i) {
    double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    if (std::fabs(d) < fpmin) d = fpmin;
    c = b + an / c;
    if (std::fabs(c) < fpmin) c = fpmin;
    d = 1 / d;
    double del = d * c;
    h *= del;
    if (std::fabs(del - 1) < 1e-15) break;
  }
  return std::exp(-x + a * std::log(x) - gln) * h;
}

// P(X >= chi2) for X ~ chi-square with dof degrees of freedom.
inline double chi2_pvalue(double chi2, int dof) { return dof > 0 ? gamma_q(0.5 * dof, 0.5 * chi2) : 1.0; }

// Per-test significance so that a family of num_tests tests has overall level alpha (Sidak).
inline double sidak_alpha(double alpha, int num_tests) { return 1.0 - std::pow(1.0 - alpha, 1.0 / num_tests); }

struct Chi2Result {
  double chi2 = 0, p = 0;
  int dof = 0;
  std::string message;  // non-empty on a hard failure (samples where the pdf is zero)
};

// Pearson chi-square of observed vs expected counts. Cells with expected < min_expected are pooled
// into one cell (Mitsuba); the pool is kept as a cell if it reaches min_expected, else it is merged
// into the smallest regular cell. Samples in a cell whose expected count is 0 are a hard failure.
inline Chi2Result chi2_test(const std::vector<double>& observed, const std::vector<double>& expected,
                            double min_expected = 5.0) {
  Chi2Result r;
  std::vector<std::pair<double, double>> cells;  // (observed, expected)
  double pool_o = 0, pool_e = 0;
  for (size_t i = 0; i < observed.size(); ++i) {
    if (expected[i] <= 0 && observed[i] > 0) {
      r.message = "cell " + std::to_string(i) + " has " + std::to_string(observed[i]) + " samples but expected 0";
      r.p = 0;
      return r;
    }
    if (expected[i] < min_expected) {
      pool_o += observed[i];
      pool_e += expected[i];
    } else {
      cells.push_back({observed[i], expected[i]});
    }
  }
  if (pool_e >= min_expected || cells.empty()) {
    if (pool_e > 0) cells.push_back({pool_o, pool_e});
    else if (pool_o > 0) { r.message = "pooled cells have samples but expected 0"; return r; }
  } else if (pool_e > 0 || pool_o > 0) {
    auto it = std::min_element(cells.begin(), cells.end(), [](auto a, auto b) { return a.second < b.second; });
    it->first += pool_o;
    it->second += pool_e;
  }
  for (auto [o, e] : cells) r.chi2 += (o - e) * (o - e) / e;
  r.dof = int(cells.size()) - 1;
  r.p = chi2_pvalue(r.chi2, r.dof);
  return r;
}

// The sphere of directions cut into theta_res x phi_res cells (theta from +z, phi = atan2(y, x)).
struct SphereGrid {
  int theta_res = 10, phi_res = 20;
  int cells() const { return theta_res * phi_res; }
  int cell_of(Vec3 w) const {
    float theta = std::acos(clamp(w.z, -1.0f, 1.0f));
    float phi = std::atan2(w.y, w.x);
    if (phi < 0) phi += 2 * kPi;
    int it = std::min(int(theta / kPi * float(theta_res)), theta_res - 1);
    int ip = std::min(int(phi / (2 * kPi) * float(phi_res)), phi_res - 1);
    return it * phi_res + ip;
  }
  // Integral of pdf over each cell: midpoint rule in (theta, phi) with the solid-angle factor
  // sin(theta), on (4 sub) x sub points per cell: theta is refined more because lobes peaked at a
  // pole (a smooth conductor seen at normal incidence) are narrow in theta.
  std::vector<double> integrate(const std::function<double(Vec3)>& pdf, int sub = 32) const {
    std::vector<double> out(size_t(cells()), 0.0);
    const int st_sub = 4 * sub;
    const double dt = M_PI / (theta_res * st_sub), dp = 2 * M_PI / (phi_res * sub);
    for (int it = 0; it < theta_res * st_sub; ++it) {
      double theta = (it + 0.5) * dt, st = std::sin(theta), ct = std::cos(theta);
      for (int ip = 0; ip < phi_res * sub; ++ip) {
        double phi = (ip + 0.5) * dp;
        Vec3 w{float(st * std::cos(phi)), float(st * std::sin(phi)), float(ct)};
        out[size_t((it / st_sub) * phi_res + ip / sub)] += pdf(w) * st * dt * dp;
      }
    }
    return out;
  }
};

struct SphereChi2 {
  Chi2Result result;
  double pdf_integral = 0;   // integral of pdf over the sphere
  double success = 0;        // fraction of calls that produced a sample
};

// Draw n samples with sample(rng, w) (false = no sample), histogram them on the grid and compare
// with n * (integral of pdf over each cell). The failures form one extra cell whose expected
// count is n * (1 - integral of pdf), so a pdf that is too small or too large everywhere is caught.
inline SphereChi2 sphere_chi2(const std::function<bool(Pcg32&, Vec3&)>& sample, const std::function<double(Vec3)>& pdf,
                              int n, uint64_t seed, SphereGrid grid = {}, int sub = 32) {
  SphereChi2 out;
  std::vector<double> observed(size_t(grid.cells()) + 1, 0.0);
  Pcg32 rng(seed, 7);
  int ok = 0;
  for (int i = 0; i < n; ++i) {
    Vec3 w;
    if (!sample(rng, w)) continue;
    ++ok;
    observed[size_t(grid.cell_of(w))] += 1;
  }
  observed.back() = double(n - ok);
  std::vector<double> expected = grid.integrate(pdf, sub);
  double integral = 0;
  for (double& e : expected) {
    integral += e;
    e *= n;
  }
  expected.push_back(std::max(0.0, 1.0 - integral) * n);
  out.pdf_integral = integral;
  out.success = double(ok) / n;
  out.result = chi2_test(observed, expected);
  return out;
}

inline std::string describe(const Chi2Result& r) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "chi2 = %.2f, dof = %d, p = %.3g", r.chi2, r.dof, r.p);
  return std::string(buf) + (r.message.empty() ? "" : " (" + r.message + ")");
}

}  // namespace rl::stat
