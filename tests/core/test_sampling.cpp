// Chi-square tests of every sample_* / *_pdf pair in core/sampling.h (fixed seeds: deterministic).
#include <doctest/doctest.h>

#include "core/rng.h"
#include "core/sampling.h"
#include "stat_utils.h"

using namespace rl;

namespace {

// Number of chi-square tests in this file; each uses the Sidak-corrected level so that the whole
// file has a false-alarm rate of 1%.
constexpr int kTests = 14;
const double kAlpha = stat::sidak_alpha(0.01, kTests);

void check_chi2(const stat::Chi2Result& r) {
  INFO(stat::describe(r));
  CHECK(r.message.empty());
  CHECK(r.p > kAlpha);
}

}  // namespace

TEST_SUITE("sampling") {

TEST_CASE("sampling: chi-square test machinery rejects a wrong pdf") {
  // The uniform sphere sampled but tested against the cosine pdf: must fail decisively.
  auto r = stat::sphere_chi2([](Pcg32& rng, Vec3& w) { w = sample_uniform_sphere(rng.next_2d()); return true; },
                             [](Vec3 w) { return double(cosine_hemisphere_pdf(w.z)); }, 20000, 1);
  CHECK(r.result.p < 1e-6);
  // A 3% error in a hemisphere's mass must be caught too.
  auto r2 = stat::sphere_chi2([](Pcg32& rng, Vec3& w) { w = sample_uniform_hemisphere(rng.next_2d()); return true; },
                              [](Vec3 w) { return w.z > 0 ? (w.x > 0 ? 1.03 : 0.97) * kInv2Pi : 0.0; }, 200000, 2);
  CHECK(r2.result.p < 1e-4);
  CHECK(stat::chi2_pvalue(3.84, 1) == doctest::Approx(0.05).epsilon(0.01).scale(1e-9));
  CHECK(stat::chi2_pvalue(18.307, 10) == doctest::Approx(0.05).epsilon(0.01).scale(1e-9));
  CHECK(stat::chi2_pvalue(124.342, 100) == doctest::Approx(0.05).epsilon(0.01).scale(1e-9));
}

TEST_CASE("sampling: cosine hemisphere matches cosine_hemisphere_pdf") {
  auto r = stat::sphere_chi2([](Pcg32& rng, Vec3& w) { w = sample_cosine_hemisphere(rng.next_2d()); return w.z > 0; },
                             [](Vec3 w) { return double(cosine_hemisphere_pdf(w.z)); }, 200000, 11);
  CHECK(r.pdf_integral == doctest::Approx(1.0).epsilon(1e-3).scale(1e-9));
  check_chi2(r.result);
}

TEST_CASE("sampling: uniform sphere and hemisphere") {
  auto r = stat::sphere_chi2([](Pcg32& rng, Vec3& w) { w = sample_uniform_sphere(rng.next_2d()); return true; },
                             [](Vec3) { return double(uniform_sphere_pdf()); }, 200000, 12);
  CHECK(r.pdf_integral == doctest::Approx(1.0).epsilon(1e-3).scale(1e-9));
  check_chi2(r.result);
  auto h = stat::sphere_chi2([](Pcg32& rng, Vec3& w) { w = sample_uniform_hemisphere(rng.next_2d()); return true; },
                             [](Vec3 w) { return w.z > 0 ? double(uniform_hemisphere_pdf()) : 0.0; }, 200000, 13);
  check_chi2(h.result);
}

TEST_CASE("sampling: uniform cone") {
  for (float cos_max : {0.3f, 0.9f}) {
    CAPTURE(cos_max);
    stat::SphereGrid grid{40, 20};
    auto r = stat::sphere_chi2(
        [&](Pcg32& rng, Vec3& w) { w = sample_uniform_cone(rng.next_2d(), cos_max); return true; },
        [&](Vec3 w) { return w.z >= cos_max ? double(uniform_cone_pdf(cos_max)) : 0.0; }, 200000, 14, grid, 16);
    CHECK(r.pdf_integral == doctest::Approx(1.0).epsilon(3e-3).scale(1e-9));
    check_chi2(r.result);
    // Every sample lies inside the cone and is a unit vector.
    Pcg32 rng(3);
    for (int i = 0; i < 1000; ++i) {
      Vec3 w = sample_uniform_cone(rng.next_2d(), cos_max);
      CHECK(w.z >= cos_max - 1e-6f);
      CHECK(length(w) == doctest::Approx(1.0f).epsilon(1e-5).scale(1e-9));
    }
  }
}

TEST_CASE("sampling: uniform triangle is uniform in barycentric space") {
  // Histogram of (b0, b1) on an R x R grid of the unit square; the triangle b0 + b1 <= 1 covers
  // full cells below the anti-diagonal and half cells on it (exact expected counts, density 2).
  const int R = 16, n = 200000;
  std::vector<double> observed(R * R, 0.0), expected(R * R, 0.0);
  Pcg32 rng(15);
  for (int i = 0; i < n; ++i) {
    Vec3 b = sample_uniform_triangle(rng.next_2d());
    REQUIRE(b.x >= 0);
    REQUIRE(b.y >= 0);
    REQUIRE(b.z >= -1e-6f);
    CHECK(b.x + b.y + b.z == doctest::Approx(1.0f));
    int ix = std::min(int(b.x * R), R - 1), iy = std::min(int(b.y * R), R - 1);
    observed[size_t(iy * R + ix)] += 1;
  }
  for (int iy = 0; iy < R; ++iy)
    for (int ix = 0; ix < R; ++ix) {
      double area = ix + iy + 2 <= R ? 1.0 : (ix + iy + 1 == R ? 0.5 : 0.0);
      expected[size_t(iy * R + ix)] = 2.0 * area / (R * R) * n;
    }
  check_chi2(stat::chi2_test(observed, expected));
}

TEST_CASE("sampling: alias table frequencies match the weights, zero weights never sampled") {
  const std::vector<float> w = {1, 0, 3, 0.5f, 0, 10, 2, 0.02f, 7, 0, 4.5f, 1};
  AliasTable table(w);
  double total = 0;
  for (float x : w) total += x;
  CHECK(table.total_weight() == doctest::Approx(total));
  for (size_t i = 0; i < w.size(); ++i) CHECK(table.pmf(uint32_t(i)) == doctest::Approx(w[i] / total));
  const int n = 300000;
  std::vector<double> observed(w.size(), 0.0), expected(w.size(), 0.0);
  Pcg32 rng(16);
  for (int i = 0; i < n; ++i) {
    float pmf = 0, ur = 0;
    uint32_t k = table.sample(rng.next_float(), &pmf, &ur);
    REQUIRE(k < w.size());
    CHECK(pmf == table.pmf(k));
    CHECK((ur >= 0 && ur < 1));
    observed[k] += 1;
  }
  for (size_t i = 0; i < w.size(); ++i) expected[i] = w[i] / total * n;
  check_chi2(stat::chi2_test(observed, expected));
  // Degenerate tables: empty or all-zero weights give an empty table, never an index with pmf > 0.
  AliasTable empty(std::vector<float>{0, 0});
  float pmf = 1;
  empty.sample(0.5f, &pmf);
  CHECK(pmf == 0);
  // The remapped u is itself uniform (used to reuse one random number): check its mean.
  double sum = 0;
  for (int i = 0; i < 100000; ++i) {
    float ur;
    table.sample(rng.next_float(), nullptr, &ur);
    sum += ur;
  }
  CHECK(sum / 100000 == doctest::Approx(0.5).epsilon(0.01).scale(1e-9));
}

TEST_CASE("sampling: Distribution1D histogram matches its pdf") {
  const std::vector<float> f = {0, 1, 5, 0, 2, 0.5f, 0, 3};
  Distribution1D d(f);
  CHECK(d.integral() == doctest::Approx((1 + 5 + 2 + 0.5 + 3) / 8.0));
  const int sub = 4, bins = int(f.size()) * sub, n = 200000;
  std::vector<double> observed(size_t(bins), 0.0), expected(size_t(bins), 0.0);
  Pcg32 rng(17);
  for (int i = 0; i < n; ++i) {
    float pdf;
    int off;
    float x = d.sample_continuous(rng.next_float(), &pdf, &off);
    REQUIRE((x >= 0 && x < 1));
    CHECK(pdf == doctest::Approx(d.pdf(x)));
    CHECK(f[size_t(off)] > 0);
    observed[size_t(std::min(int(x * bins), bins - 1))] += 1;
  }
  for (int b = 0; b < bins; ++b) expected[size_t(b)] = d.pdf((b + 0.5f) / bins) / bins * n;
  check_chi2(stat::chi2_test(observed, expected));
}

TEST_CASE("sampling: Distribution2D histogram matches its pdf") {
  const int nu = 8, nv = 5;
  std::vector<float> f(nu * nv);
  for (int v = 0; v < nv; ++v)
    for (int u = 0; u < nu; ++u) f[size_t(v * nu + u)] = ((u * 7 + v * 3) % 5 == 0) ? 0.0f : float(1 + (u * v) % 4);
  f[size_t(2 * nu)] = 40;  // a bright texel
  for (int u = 0; u < nu; ++u) f[size_t(3 * nu + u)] = 0;  // an all-zero row
  Distribution2D d(f, nu, nv);
  const int n = 300000;
  std::vector<double> observed(size_t(nu * nv), 0.0), expected(size_t(nu * nv), 0.0);
  Pcg32 rng(18);
  double integral = 0;
  for (int v = 0; v < nv; ++v)
    for (int u = 0; u < nu; ++u) {
      double p = d.pdf({(u + 0.5f) / nu, (v + 0.5f) / nv}) / (nu * nv);
      expected[size_t(v * nu + u)] = p * n;
      integral += p;
      if (f[size_t(v * nu + u)] == 0) CHECK(p == 0);
    }
  CHECK(integral == doctest::Approx(1.0).epsilon(1e-4).scale(1e-9));
  for (int i = 0; i < n; ++i) {
    float pdf;
    Vec2 p = d.sample_continuous(rng.next_2d(), &pdf);
    REQUIRE((p.x >= 0 && p.x < 1 && p.y >= 0 && p.y < 1));
    CHECK(pdf == doctest::Approx(d.pdf(p)).epsilon(1e-4).scale(1e-9));
    observed[size_t(std::min(int(p.y * nv), nv - 1) * nu + std::min(int(p.x * nu), nu - 1))] += 1;
  }
  check_chi2(stat::chi2_test(observed, expected));
}

TEST_CASE("sampling: tent matches the triangle density") {
  const float r = 1.5f;
  const int bins = 30, n = 200000;
  // CDF of the tent on [-r, r]: x <= 0: (x + r)^2 / (2 r^2); x >= 0: 1 - (r - x)^2 / (2 r^2).
  auto cdf = [&](double x) { return x <= 0 ? sqr(float(x + r)) / (2 * r * r) : 1 - sqr(float(r - x)) / (2 * r * r); };
  std::vector<double> observed(bins, 0.0), expected(bins, 0.0);
  Pcg32 rng(19);
  for (int i = 0; i < n; ++i) {
    float x = sample_tent(rng.next_float(), r);
    REQUIRE((x >= -r && x <= r));
    observed[size_t(std::clamp(int((x + r) / (2 * r) * bins), 0, bins - 1))] += 1;
  }
  for (int b = 0; b < bins; ++b) {
    double x0 = -r + 2.0 * r * b / bins, x1 = -r + 2.0 * r * (b + 1) / bins;
    expected[size_t(b)] = (cdf(x1) - cdf(x0)) * n;
  }
  check_chi2(stat::chi2_test(observed, expected));
}

TEST_CASE("sampling: concentric disk is uniform on the unit disk") {
  // Map the disk sample to the hemisphere by z = sqrt(1 - r^2) (Malley): uniform disk <=> cosine.
  // Instead test the disk itself on a polar grid: equal-area rings r in [sqrt(i/R), sqrt((i+1)/R)).
  const int R = 8, P = 16, n = 160000;
  std::vector<double> observed(R * P, 0.0), expected(R * P, double(n) / (R * P));
  Pcg32 rng(20);
  for (int i = 0; i < n; ++i) {
    Vec2 d = sample_uniform_disk_concentric(rng.next_2d());
    float r2 = d.x * d.x + d.y * d.y;
    REQUIRE(r2 <= 1.0f + 1e-6f);
    float phi = std::atan2(d.y, d.x);
    if (phi < 0) phi += 2 * kPi;
    int ir = std::min(int(r2 * R), R - 1), ip = std::min(int(phi / (2 * kPi) * P), P - 1);
    observed[size_t(ir * P + ip)] += 1;
  }
  check_chi2(stat::chi2_test(observed, expected));
}

TEST_CASE("sampling: radical inverse in every prime base (van der Corput digits, exact)") {
  CHECK(radical_inverse(0, 1) == 0.5f);
  CHECK(radical_inverse(0, 6) == 0.375f);  // 110 -> 0.011
  CHECK(radical_inverse(1, 1) == doctest::Approx(1.0 / 3));
  CHECK(radical_inverse(1, 5) == doctest::Approx(2.0 / 3 + 1.0 / 9));  // 12 in base 3 -> 0.21
  const uint32_t primes[] = {2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53};
  for (uint32_t b = 0; b < 16; ++b) {
    for (uint64_t a : {0ull, 1ull, 2ull, 7ull, 100ull, 12345ull, 987654321ull, (1ull << 40) + 3}) {
      double v = 0, scale = 1.0 / primes[b];  // digit by digit, most significant last
      for (uint64_t x = a; x; x /= primes[b], scale /= primes[b]) v += double(x % primes[b]) * scale;
      CAPTURE(b);
      CAPTURE(a);
      CHECK(radical_inverse(b, a) == doctest::Approx(v).epsilon(1e-6));
    }
  }
}

TEST_CASE("sampling: sincos_turns is sin and cos of 2 pi u within 3e-7 over [0, 1]") {
  double worst = 0;
  for (int i = 0; i <= 1 << 20; ++i) {
    const float u = float(i) / float(1 << 20);
    float s, c;
    sincos_turns(u, s, c);
    const double phi = 2 * 3.14159265358979323846 * double(u);
    worst = std::max({worst, std::fabs(double(s) - std::sin(phi)), std::fabs(double(c) - std::cos(phi))});
  }
  MESSAGE("worst error ", worst);
  CHECK(worst < 3e-7);
  float s, c;
  sincos_turns(0.25f, s, c);  // quadrants land exactly
  CHECK(s == 1.0f);
  CHECK(c == 0.0f);
  sincos_turns(0.5f, s, c);
  CHECK(c == -1.0f);
}

}  // TEST_SUITE
