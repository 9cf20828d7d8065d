// Tests of coated diffuse (scene/bsdf_coated.h, scene/coated.h): sampling against the pdf by
// chi-square, the delta lobe of a smooth coat, energy (numerically integrated albedo against the
// closed form for a smooth coat and against the dielectric BSDF's own lobes for a rough one), the
// coat table against its quadrature, flags.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "core/rng.h"
#include "scene/bsdf.h"
#include "scene/coated.h"
#include "bsdf_test_utils.h"
#include "stat_utils.h"

using namespace rl;
using rl::test::coated;
using rl::test::dir;

namespace {

constexpr int kTests = 14;  // chi-square tests in this file (Sidak correction)
const double kAlpha = stat::sidak_alpha(0.01, kTests);

Bsdf dielectric(float eta, float alpha) {
  Material m;
  m.type = Material::Type::dielectric;
  m.ior = eta;
  m.alpha_x = m.alpha_y = alpha;
  return make_bsdf(m, Rgb(1));
}

// ∫ g(mu) dmu over [0, 1] by the midpoint rule on n cells, in double.
template <class G>
double integrate01(G g, int n) {
  double s = 0;
  for (int i = 0; i < n; ++i) s += g((i + 0.5) / n);
  return s / n;
}

// ∫ g(w) over the upper hemisphere, stratified in (theta, phi) with one jittered sample per cell.
template <class G>
double integrate_hemisphere(G g, int n, uint64_t seed) {
  Pcg32 rng(seed);
  double sum = 0;
  const double dt = 0.5 * M_PI / n, dp = M_PI / n;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      const double theta = (i + rng.next_float()) * dt, phi = (j + rng.next_float()) * dp, st = std::sin(theta);
      sum += g(Vec3{float(st * std::cos(phi)), float(st * std::sin(phi)), float(std::cos(theta))}) * st;
    }
  return sum * dt * dp;
}

// Directional albedo of b from wo (upper hemisphere): ∫ f cos over the non-delta lobes plus the
// smooth coat's delta weight F(cos o).
double albedo(const Bsdf& b, Vec3 wo, int n = 256) {
  double a = integrate_hemisphere([&](Vec3 w) { return double(bsdf_eval(b, wo, w).y * w.z); }, n, 3);
  if (bsdf_has_delta(b)) a += fresnel_dielectric(wo.z, b.ior);
  return a;
}

struct Case {
  std::string name;
  Bsdf b;
  Vec3 wo;
};

std::vector<Case> cases() {
  std::vector<Case> c;
  const Bsdf rough = coated(Rgb(0.6f, 0.4f, 0.2f), 1.5f, 0.3f, 0.3f), smooth = coated(Rgb(0.6f, 0.4f, 0.2f), 1.5f, 0, 0);
  for (float t : {0.0f, 45.0f, 80.0f, 89.0f}) c.push_back({"rough 0.3 theta_o=" + std::to_string(t), rough, dir(t, 30)});
  for (float t : {0.0f, 60.0f, 89.0f}) c.push_back({"smooth theta_o=" + std::to_string(t), smooth, dir(t, 10)});
  c.push_back({"rough 0.05 theta_o=70", coated(Rgb(0.2f), 1.33f, 0.05f, 0.05f), dir(70, 50)});
  c.push_back({"rough 0.1/0.4 theta_o=50", coated(Rgb(0.8f), 1.5f, 0.1f, 0.4f), dir(50, 80)});
  c.push_back({"black base rough 0.2 theta_o=30", coated(Rgb(0), 1.5f, 0.2f, 0.2f), dir(30, 0)});
  c.push_back({"white base rough 0.8 theta_o=60", coated(Rgb(1), 2.0f, 0.8f, 0.8f), dir(60, 0)});
  // Two-sided like pbrt-v4: seen from below, it reflects into the lower hemisphere.
  c.push_back({"rough 0.3 from below theta_o=135", rough, dir(135, 200)});
  c.push_back({"smooth from below theta_o=160", smooth, dir(160, 20)});
  return c;
}

}  // namespace

TEST_SUITE("bsdf") {

TEST_CASE("coated: chi-square of bsdf_sample against bsdf_pdf, rough and smooth coats, grazing and from below") {
  const std::vector<Case> cs = cases();
  REQUIRE(int(cs.size()) <= kTests);
  uint64_t seed = 500;
  for (const Case& c : cs) {
    CAPTURE(c.name);
    auto sample = [&](Pcg32& rng, Vec3& w) {
      BsdfSample s;
      const float ul = rng.next_float();
      const Vec2 u = rng.next_2d();
      if (!bsdf_sample(c.b, c.wo, ul, u, s) || s.is_delta) return false;  // the delta has no density
      w = s.wi;
      return true;
    };
    auto r = stat::sphere_chi2(sample, [&](Vec3 w) { return double(bsdf_pdf(c.b, c.wo, w)); }, 200000, seed++);
    INFO(stat::describe(r.result), ", pdf integral = ", r.pdf_integral, ", success = ", r.success);
    CHECK(r.result.message.empty());
    CHECK(r.result.p > kAlpha);
    CHECK(r.pdf_integral <= 1.003);
    // The pdf (the non-delta lobes' times their probability) integrates to the non-delta success rate,
    // up to its binomial noise (large when the delta takes most samples: 96 % at 89 degrees).
    CHECK(std::fabs(r.pdf_integral - r.success) <= 4 * std::sqrt(r.success * (1 - r.success) / 200000) + 0.005 * r.success);
  }
}

TEST_CASE("coated: sampled f and pdf equal eval and pdf; a smooth coat's delta is the Fresnel mirror") {
  for (const Case& c : cases()) {
    CAPTURE(c.name);
    Pcg32 rng(7);
    int bad = 0, ok = 0, deltas = 0;
    for (int i = 0; i < 20000; ++i) {
      BsdfSample s;
      if (!bsdf_sample(c.b, c.wo, rng.next_float(), rng.next_2d(), s)) continue;
      ++ok;
      CHECK(s.wi.z * c.wo.z > 0);
      if (s.is_delta) {
        ++deltas;
        const float F = fresnel_dielectric(std::fabs(c.wo.z), c.b.ior);
        CHECK(s.wi.x == doctest::Approx(-c.wo.x));
        CHECK(s.wi.z == doctest::Approx(c.wo.z));
        CHECK(s.f.x * std::fabs(s.wi.z) == doctest::Approx(F).epsilon(1e-4));  // the delta's weight
        CHECK(s.pdf < 1);                                                      // its lobe probability
        continue;
      }
      const Rgb f = bsdf_eval(c.b, c.wo, s.wi);
      const float pdf = bsdf_pdf(c.b, c.wo, s.wi);
      auto close = [](float a, float b) { return std::fabs(a - b) <= 2e-3f * std::max(std::fabs(a), std::fabs(b)) + 1e-6f; };
      if (!close(pdf, s.pdf) || !close(f.x, s.f.x) || !close(f.z, s.f.z)) ++bad;
    }
    CHECK(ok > 1000);
    CHECK(bad <= ok / 2000);
    CHECK((deltas > 0) == bsdf_has_delta(c.b));
  }
}

TEST_CASE("coated: the coat table follows its quadrature; the quadrature matches the dielectric BSDF's lobes") {
  for (float eta : {1.33f, 1.5f, 2.0f})
    for (float alpha : {0.01f, 0.05f, 0.3f, 1.0f}) {
      CAPTURE(eta);
      CAPTURE(alpha);
      const Bsdf b = coated(Rgb(0.5f), eta, alpha, alpha);
      // Linear interpolation on 16 nodes: T bends most at grazing (a minimum near mu ~ 0.05 for glossy
      // coats, where the visible normals start to face the light), where cos weighs it least.
      double worst_grazing = 0, worst = 0;
      for (int i = 4; i <= 200; ++i) {
        const double mu = i / 200.0;
        const double e = std::fabs(bsdf_detail::coat_transmittance(b, float(mu)) - coat_transmittance(eta, alpha, mu));
        (mu < 0.2 ? worst_grazing : worst) = std::max(mu < 0.2 ? worst_grazing : worst, e);
      }
      CHECK(worst_grazing < 8e-3);
      CHECK(worst < 3.5e-3);
    }
  // T(mu) is the dielectric's transmission lobe in energy terms: eta^2 ∫ f_t |cos i| (f_t carries
  // the radiance factor 1/eta^2); E_int(mu) is its reflection lobe seen from inside.
  for (float alpha : {0.2f, 0.5f}) {
    const Bsdf g = dielectric(1.5f, alpha);
    for (float t : {0.0f, 50.0f, 80.0f}) {
      CAPTURE(alpha);
      CAPTURE(t);
      const Vec3 wo = dir(t, 0), below{wo.x, wo.y, -wo.z};
      const double tr = 2.25 * integrate_hemisphere([&](Vec3 w) { return double(bsdf_eval(g, wo, Vec3{w.x, w.y, -w.z}).x * w.z); }, 256, 5);
      CHECK(coat_transmittance(1.5f, alpha, wo.z) == doctest::Approx(tr).epsilon(0.01));
      const double ei = integrate_hemisphere([&](Vec3 w) { return double(bsdf_eval(g, below, Vec3{w.x, w.y, -w.z}).x * w.z); }, 256, 6);
      CHECK(coat_internal_albedo(1.5f, alpha, wo.z) == doctest::Approx(ei).epsilon(0.01));
    }
  }
}

TEST_CASE("coated: smooth coat: closed-form Fdr and albedo (Walsh's Fresnel integral), energy conserving at R = 1") {
  for (double eta : {1.33, 1.5, 2.0}) {
    CAPTURE(eta);
    // Fdr_ext by the closed form against a fine numerical integral of the Fresnel term.
    const double ext = integrate01([&](double mu) { return 2 * mu * fresnel_dielectric(float(mu), float(eta)); }, 200000);
    CHECK(fresnel_diffuse_reflectance(eta) == doctest::Approx(ext).epsilon(1e-5));
    // Inside, 1 - Fdr_int = (1 - Fdr_ext) / eta^2 (the interface's reciprocity).
    const double a = 1 - fresnel_diffuse_reflectance(eta);
    CHECK(coat_internal_reflectance(float(eta), 0) == doctest::Approx(1 - a / (eta * eta)).epsilon(1e-5));
    for (float R : {0.0f, 0.3f, 0.8f, 1.0f}) {
      CAPTURE(R);
      const Bsdf b = coated(Rgb(R), float(eta), 0, 0);
      // Normal incidence: F0 + (1 - F0) T-weighted base = F0 + (1 - F0) R a / (eta^2 (1 - R) + R a).
      const double f0 = fresnel_dielectric(1, float(eta));
      const double exact = f0 + (1 - f0) * R * a / (eta * eta * (1 - R) + R * a);
      // f depends on cos i alone there: ∫ f cos = 2 pi ∫ f(mu) mu dmu.
      const double numeric = f0 + integrate01([&](double mu) {
        const Vec3 wi{float(std::sqrt(1 - mu * mu)), 0, float(mu)};
        return 2 * M_PI * mu * double(bsdf_eval(b, Vec3{0, 0, 1}, wi).x);
      }, 20000);
      CHECK(numeric == doctest::Approx(exact).epsilon(5e-5));
      if (R == 1.0f)
        for (float t : {0.0f, 40.0f, 75.0f, 88.0f}) CHECK(albedo(b, dir(t, 0)) == doctest::Approx(1.0).epsilon(2e-3));
    }
  }
}

TEST_CASE("coated: rough coat energy: R = 0 gives the coat's specular albedo, R = 1 at most 1, the formula's albedo") {
  for (float alpha : {0.1f, 0.3f, 0.7f}) {
    const Bsdf black = coated(Rgb(0), 1.5f, alpha, alpha), white = coated(Rgb(1), 1.5f, alpha, alpha);
    const Bsdf g = dielectric(1.5f, alpha);
    const double fdr = coat_internal_reflectance(1.5f, alpha);
    const double tbar = 2 * integrate01([&](double mu) { return mu * coat_transmittance(1.5f, alpha, mu); }, 400);
    for (float t : {0.0f, 45.0f, 80.0f}) {
      CAPTURE(alpha);
      CAPTURE(t);
      const Vec3 wo = dir(t, 30);
      // The coat alone: the dielectric BSDF's reflection lobe, integrated the same way.
      const double spec = integrate_hemisphere([&](Vec3 w) { return double(bsdf_eval(g, wo, w).x * w.z); }, 256, 3);
      const double a0 = albedo(black, wo), a1 = albedo(white, wo);
      CHECK(a0 == doctest::Approx(spec).epsilon(1e-3));
      CHECK(a1 <= 1.0 + 2e-3);
      // The formula's base term integrates to T(mu_o) R Tbar / (eta^2 (1 - R Fdr)), Tbar = 2 ∫ T mu.
      const double base = coat_transmittance(1.5f, alpha, wo.z) * tbar / (2.25 * (1 - fdr));
      CHECK(a1 == doctest::Approx(spec + base).epsilon(4e-3));
    }
  }
}

TEST_CASE("coated: flags, roughness, reciprocity") {
  const Bsdf smooth = coated(Rgb(0.5f), 1.5f, 0, 0), rough = coated(Rgb(0.5f), 1.5f, 0.2f, 0.8f);
  CHECK_FALSE(bsdf_is_delta(smooth));
  CHECK(bsdf_has_delta(smooth));
  CHECK_FALSE(bsdf_is_delta(rough));
  CHECK_FALSE(bsdf_has_delta(rough));
  CHECK_FALSE(bsdf_has_delta(coated(Rgb(0.5f), 1.0f, 0, 0)));  // index-matched: no coat to reflect
  CHECK(bsdf_roughness(smooth) == 1.0f);                       // its only non-delta lobe: the base
  // The delta lobe whole (what ReSTIR DI adds deterministically): the mirror with weight F(cos o).
  BsdfSample d;
  REQUIRE(bsdf_delta_lobe(smooth, dir(50, 30), d));
  CHECK(d.is_delta);
  CHECK(d.pdf == 1.0f);
  CHECK(d.wi.x == doctest::Approx(-dir(50, 30).x));
  CHECK(d.f.x * d.wi.z == doctest::Approx(fresnel_dielectric(dir(50, 30).z, 1.5f)));
  REQUIRE(bsdf_delta_lobe(smooth, -dir(50, 30), d));  // two-sided
  CHECK(d.wi.z == doctest::Approx(-dir(50, 30).z));
  CHECK_FALSE(bsdf_delta_lobe(rough, dir(50, 30), d));
  CHECK_FALSE(bsdf_delta_lobe(dielectric(1.5f, 0), dir(50, 30), d));  // all-delta BSDFs are sampled
  CHECK(bsdf_roughness(rough) == doctest::Approx(0.4f));
  Pcg32 rng(9);
  for (const Bsdf& b : {smooth, rough})
    for (int i = 0; i < 2000; ++i) {
      const Vec3 a = sample_uniform_sphere(rng.next_2d()), c = sample_uniform_sphere(rng.next_2d());
      const Rgb fac = bsdf_eval(b, a, c), fca = bsdf_eval(b, c, a);
      CHECK(fac.x == doctest::Approx(fca.x).epsilon(1e-3).scale(1e-9));
      if (a.z * c.z <= 0) CHECK(is_black(fac));
    }
}

}  // TEST_SUITE
