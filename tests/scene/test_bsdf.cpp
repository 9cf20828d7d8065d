// Statistical and analytic tests of scene/bsdf.h: every bsdf_sample against bsdf_pdf by
// chi-square over the whole sphere, sample/eval/pdf consistency, reciprocity, energy, NaN safety.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "core/rng.h"
#include "scene/bsdf.h"
#include "scene/coated.h"
#include "scene/microfacet.h"
#include "bsdf_test_utils.h"
#include "stat_utils.h"

using namespace rl;
using rl::test::coated;
using rl::test::dir;

namespace {

constexpr int kTests = 24;  // chi-square tests in this file (Sidak correction)
const double kAlpha = stat::sidak_alpha(0.01, kTests);

Bsdf diffuse(Rgb r) {
  Material m;
  m.type = Material::Type::diffuse;
  return make_bsdf(m, r);
}
Bsdf conductor(float ax, float ay) {
  Material m;
  m.type = Material::Type::conductor;  // default eta/k: copper
  m.alpha_x = ax;
  m.alpha_y = ay;
  return make_bsdf(m, m.reflectance);
}
Bsdf conductor_reflectance(Rgb r, float alpha) {
  Material m;
  m.type = Material::Type::conductor;
  m.use_reflectance = true;
  m.alpha_x = m.alpha_y = alpha;
  return make_bsdf(m, r);
}
Bsdf dielectric(float ior, float ax, float ay) {
  Material m;
  m.type = Material::Type::dielectric;
  m.ior = ior;
  m.alpha_x = ax;
  m.alpha_y = ay;
  return make_bsdf(m, Rgb(1));
}

struct Case {
  std::string name;
  Bsdf b;
  Vec3 wo;
};

std::vector<Case> rough_cases() {
  std::vector<Case> c;
  const Bsdf d = diffuse(Rgb(0.8f));
  for (float t : {0.0f, 45.0f, 89.0f, 120.0f}) c.push_back({"diffuse theta_o=" + std::to_string(t), d, dir(t, 30)});
  struct A { const char* n; float ax, ay; };
  for (A a : {A{"0.05", 0.05f, 0.05f}, A{"0.3", 0.3f, 0.3f}, A{"0.1/0.4", 0.1f, 0.4f}})
    for (float t : {0.0f, 45.0f, 80.0f})
      c.push_back({std::string("conductor alpha=") + a.n + " theta_o=" + std::to_string(t), conductor(a.ax, a.ay), dir(t, 20)});
  // Two-sided like pbrt-v4: a conductor seen from below reflects into the lower hemisphere.
  c.push_back({"conductor alpha=0.3 theta_o=135", conductor(0.3f, 0.3f), dir(135, 200)});
  const Bsdf g = dielectric(1.5f, 0.3f, 0.3f);
  // Outside, then inside (below the critical angle of 41.8 deg and beyond it: mostly TIR).
  for (float t : {0.0f, 45.0f, 80.0f, 180.0f, 150.0f, 120.0f})
    c.push_back({"dielectric ior=1.5 alpha=0.3 theta_o=" + std::to_string(t), g, dir(t, 60)});
  c.push_back({"dielectric ior=1.5 alpha=0.1/0.4 theta_o=60", dielectric(1.5f, 0.1f, 0.4f), dir(60, 70)});
  c.push_back({"dielectric ior=1.33 alpha=0.05 theta_o=160", dielectric(1.33f, 0.05f, 0.05f), dir(160, 10)});
  return c;
}

bool sample_dir(const Bsdf& b, Vec3 wo, Pcg32& rng, Vec3& w) {
  BsdfSample s;
  float ul = rng.next_float();
  Vec2 u = rng.next_2d();
  if (!bsdf_sample(b, wo, ul, u, s) || s.is_delta) return false;
  w = s.wi;
  return true;
}

// Integral of g over the sphere by stratified Monte Carlo in (theta, phi): n x 2n strata, one
// jittered sample each, weighted by the solid-angle factor sin(theta). Strata uniform in theta
// resolve lobes peaked at the pole far better than strata uniform in cos(theta).
template <class G>
double integrate_sphere(G g, int n, uint64_t seed) {
  Pcg32 rng(seed);
  double sum = 0;
  const double dt = M_PI / n, dp = M_PI / n;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      double theta = (i + rng.next_float()) * dt, phi = (j + rng.next_float()) * dp;
      double st = std::sin(theta);
      Vec3 w{float(st * std::cos(phi)), float(st * std::sin(phi)), float(std::cos(theta))};
      sum += g(w) * st;
    }
  return sum * dt * dp;
}

void chi2_cases(Material::Type type, uint64_t seed, int n = 200000, stat::SphereGrid grid = {}) {
  for (const Case& c : rough_cases()) {
    if (c.b.type != type) continue;
    CAPTURE(c.name);
    auto r = stat::sphere_chi2([&](Pcg32& rng, Vec3& w) { return sample_dir(c.b, c.wo, rng, w); },
                               [&](Vec3 w) { return double(bsdf_pdf(c.b, c.wo, w)); }, n, seed++, grid);
    INFO(stat::describe(r.result), ", pdf integral = ", r.pdf_integral, ", success = ", r.success);
    CHECK(r.result.message.empty());
    CHECK(r.result.p > kAlpha);
    CHECK(r.pdf_integral <= 1.003);
    // pdf is the density of the samples that bsdf_sample returns: its mass is the success rate.
    CHECK(r.pdf_integral == doctest::Approx(r.success).epsilon(0.01).scale(1e-9));
  }
}

}  // namespace

TEST_SUITE("bsdf") {

TEST_CASE("bsdf: chi-square of bsdf_sample against bsdf_pdf: diffuse") {
  REQUIRE(int(rough_cases().size()) <= kTests);
  chi2_cases(Material::Type::diffuse, 100);
}
TEST_CASE("bsdf: chi-square of bsdf_sample against bsdf_pdf: GGX conductor") { chi2_cases(Material::Type::conductor, 200); }
TEST_CASE("bsdf: chi-square of bsdf_sample against bsdf_pdf: rough dielectric, outside and inside") {
  chi2_cases(Material::Type::dielectric, 300);
}

TEST_CASE("bsdf: pdf integrates to <= 1 (1 for diffuse) by Monte Carlo") {
  for (const Case& c : rough_cases()) {
    CAPTURE(c.name);
    double integral = integrate_sphere([&](Vec3 w) { return double(bsdf_pdf(c.b, c.wo, w)); }, 512, 5);
    CHECK(integral <= 1.01);
    if (c.b.type == Material::Type::diffuse) CHECK(integral == doctest::Approx(1.0).epsilon(0.005).scale(1e-9));
    if (c.b.type == Material::Type::conductor && c.wo.z > 0.5f) CHECK(integral > 0.9);
  }
}

TEST_CASE("bsdf: sampled f and pdf equal bsdf_eval and bsdf_pdf") {
  for (const Case& c : rough_cases()) {
    CAPTURE(c.name);
    Pcg32 rng(7);
    int bad = 0, ok = 0;
    for (int i = 0; i < 20000; ++i) {
      BsdfSample s;
      float ul = rng.next_float();
      Vec2 u = rng.next_2d();
      if (!bsdf_sample(c.b, c.wo, ul, u, s)) continue;
      ++ok;
      REQUIRE_FALSE(s.is_delta);
      Rgb f = bsdf_eval(c.b, c.wo, s.wi);
      float pdf = bsdf_pdf(c.b, c.wo, s.wi);
      auto close = [](float a, float b) { return std::fabs(a - b) <= 2e-3f * std::max(std::fabs(a), std::fabs(b)) + 1e-6f; };
      if (!close(pdf, s.pdf) || !close(f.x, s.f.x) || !close(f.y, s.f.y) || !close(f.z, s.f.z)) ++bad;
    }
    CHECK(ok > 1000);
    CHECK(bad <= ok / 2000);  // float round-off at grazing configurations only
  }
}

TEST_CASE("bsdf: reciprocity of eval; generalized reciprocity of transmission") {
  Pcg32 rng(9);
  const std::vector<Bsdf> bs = {diffuse(Rgb(0.7f)), conductor(0.3f, 0.3f), conductor(0.1f, 0.4f), dielectric(1.5f, 0.3f, 0.3f)};
  for (const Bsdf& b : bs) {
    for (int i = 0; i < 2000; ++i) {
      Vec3 a = sample_uniform_sphere(rng.next_2d()), c = sample_uniform_sphere(rng.next_2d());
      Rgb fac = bsdf_eval(b, a, c), fca = bsdf_eval(b, c, a);
      if (a.z * c.z > 0) {
        CHECK(fac.x == doctest::Approx(fca.x).epsilon(1e-3).scale(1e-9));
        CHECK(fac.z == doctest::Approx(fca.z).epsilon(1e-3).scale(1e-9));
      } else if (b.type == Material::Type::dielectric) {
        // Radiance BTDF: f(wo, wi) eta_wi^2 = f(wi, wo) eta_wo^2 (Veach 1997, sec. 5.2: generalized reciprocity f/eta_o^2 symmetric).
        float eta_a = a.z > 0 ? 1 : b.ior, eta_c = c.z > 0 ? 1 : b.ior;
        // Absolute floor 1e-6 (f is O(1) here): near-grazing transmissions of ~1e-5 differ by float round-off.
        CHECK(fac.x * eta_c * eta_c == doctest::Approx(fca.x * eta_a * eta_a).epsilon(1e-3).scale(1e-3));
      } else {
        CHECK(is_black(fac));
      }
    }
  }
}

TEST_CASE("bsdf: energy: diffuse albedo 1 integrates to 1, conductors conserve") {
  const Bsdf white = diffuse(Rgb(1));
  for (float t : {0.0f, 60.0f, 89.0f}) {
    Vec3 wo = dir(t, 0);
    double e = integrate_sphere([&](Vec3 w) { return double(bsdf_eval(white, wo, w).x * std::fabs(w.z)); }, 512, 11);
    CHECK(e == doctest::Approx(1.0).epsilon(0.005).scale(1e-9));
  }
  // Conductor with reflectance 1 (F ~ 1): single-scattering GGX loses energy with roughness but
  // never gains it; at small alpha it is nearly lossless. Estimated with the BSDF's own sampling.
  for (float alpha : {0.05f, 0.3f, 0.8f}) {
    const Bsdf b = conductor_reflectance(Rgb(1), alpha);
    for (float t : {0.0f, 45.0f, 75.0f}) {
      CAPTURE(alpha);
      CAPTURE(t);
      Vec3 wo = dir(t, 40);
      Pcg32 rng(12);
      double sum = 0, sum2 = 0;
      const int n = 50000;
      for (int i = 0; i < n; ++i) {
        BsdfSample s;
        float ul = rng.next_float();
        Vec2 u = rng.next_2d();
        double v = bsdf_sample(b, wo, ul, u, s) ? s.f.y * std::fabs(s.wi.z) / s.pdf : 0.0;
        sum += v;
        sum2 += v * v;
      }
      double mean = sum / n, se = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
      CHECK(mean <= 1.0 + 3 * se + 1e-3);
      if (alpha <= 0.05f) CHECK(mean > 0.97);
    }
  }
  // Smooth conductor with reflectance 1: the mirror returns throughput F ~ 1.
  BsdfSample s;
  REQUIRE(bsdf_sample(conductor_reflectance(Rgb(1), 0), dir(30, 0), 0.5f, {0.5f, 0.5f}, s));
  CHECK(s.is_delta);
  CHECK(s.f.x * std::fabs(s.wi.z) / s.pdf == doctest::Approx(1.0).epsilon(1e-3).scale(1e-9));
  CHECK(s.wi.z == doctest::Approx(dir(30, 0).z));
}

TEST_CASE("bsdf: smooth dielectric: Fresnel-chosen reflection/refraction, probabilities sum to 1") {
  const Bsdf g = dielectric(1.5f, 0, 0);
  CHECK(bsdf_is_delta(g));
  CHECK(fresnel_dielectric(1.0f, 1.5f) == doctest::Approx(0.04f).epsilon(1e-4).scale(1e-9));
  for (float t : {0.0f, 30.0f, 70.0f, 89.0f, 180.0f, 160.0f, 120.0f}) {
    CAPTURE(t);
    Vec3 wo = dir(t, 25);
    float R = fresnel_dielectric(wo.z, 1.5f);
    BsdfSample sr, st;
    REQUIRE(bsdf_sample(g, wo, 0.0f, {0.3f, 0.3f}, sr));  // u_lobe = 0: reflection
    CHECK(sr.is_delta);
    CHECK(sr.pdf == doctest::Approx(R));
    CHECK(sr.wi.z == doctest::Approx(wo.z));
    CHECK(sr.f.x * std::fabs(sr.wi.z) / sr.pdf == doctest::Approx(1.0f));
    bool has_t = bsdf_sample(g, wo, 0.99999f, {0.3f, 0.3f}, st);
    if (R < 1) {
      REQUIRE(has_t);
      CHECK(st.pdf == doctest::Approx(1 - R));
      CHECK(sr.pdf + st.pdf == doctest::Approx(1.0f));
      CHECK(st.wi.z * wo.z < 0);
      // Snell: eta_o sin_o = eta_i sin_i; radiance throughput (eta_o / eta_i)^2.
      float eta_o = wo.z > 0 ? 1 : 1.5f, eta_i = wo.z > 0 ? 1.5f : 1;
      float sin_o = std::sqrt(1 - wo.z * wo.z), sin_i = std::sqrt(std::max(0.0f, 1 - st.wi.z * st.wi.z));
      CHECK(eta_o * sin_o == doctest::Approx(eta_i * sin_i).epsilon(1e-3).scale(1e-9));
      CHECK(st.f.x * std::fabs(st.wi.z) / st.pdf == doctest::Approx(sqr(eta_o / eta_i)).epsilon(1e-4).scale(1e-9));
    } else {
      CHECK(R == 1.0f);  // total internal reflection: never refracts
    }
    CHECK(bsdf_pdf(g, wo, sr.wi) == 0);
    CHECK(is_black(bsdf_eval(g, wo, sr.wi)));
  }
  // Frequencies of the two lobes follow R at 60 degrees.
  Vec3 wo = dir(60, 0);
  float R = fresnel_dielectric(wo.z, 1.5f);
  Pcg32 rng(21);
  int refl = 0;
  const int n = 100000;
  for (int i = 0; i < n; ++i) {
    BsdfSample s;
    float ul = rng.next_float();
    Vec2 u = rng.next_2d();
    if (bsdf_sample(g, wo, ul, u, s) && s.wi.z > 0) ++refl;
  }
  double se = std::sqrt(R * (1 - R) / n);
  CHECK(std::fabs(double(refl) / n - R) < 4 * se);
  // Index-matched: straight through.
  BsdfSample s;
  REQUIRE(bsdf_sample(dielectric(1.0f, 0.3f, 0.3f), wo, 0.5f, {0.1f, 0.2f}, s));
  CHECK(s.wi.x == doctest::Approx(-wo.x));
  CHECK(s.wi.z == doctest::Approx(-wo.z));
  CHECK(s.f.x * std::fabs(s.wi.z) / s.pdf == doctest::Approx(1.0f));
}

TEST_CASE("bsdf: microfacet normalization: D projected area and visible normals integrate to 1") {
  for (Ggx m : {Ggx{0.05f, 0.05f}, Ggx{0.3f, 0.3f}, Ggx{0.1f, 0.4f}, Ggx{0.9f, 0.6f}}) {
    CAPTURE(m.ax);
    CAPTURE(m.ay);
    // Walter 2007 eq. 4: integral of D(wm) cos(theta_m) = 1.
    double proj = integrate_sphere([&](Vec3 w) { return double(m.d(w) * std::max(w.z, 0.0f)); }, 768, 3);
    CHECK(proj == doctest::Approx(1.0).epsilon(0.01).scale(1e-9));
    // Heitz 2014 eq. 18: integral of G1(wo) max(0, wo.wm) D(wm) / cos(theta_o) = 1.
    for (float t : {0.0f, 50.0f, 85.0f}) {
      Vec3 wo = dir(t, 35);
      double vis = integrate_sphere([&](Vec3 w) { return double(dot(wo, w) > 0 ? m.d_visible(wo, w) : 0.0f); }, 768, 4);
      CHECK(vis == doctest::Approx(1.0).epsilon(0.01).scale(1e-9));
    }
  }
  // G2 height-correlated is at most min(G1(wo), G1(wi)) and at least their product.
  Ggx m{0.4f, 0.4f};
  Vec3 a = dir(70, 0), b = dir(40, 90);
  CHECK(m.g(a, b) <= std::min(m.g1(a), m.g1(b)) + 1e-6f);
  CHECK(m.g(a, b) >= m.g1(a) * m.g1(b) - 1e-6f);
}

TEST_CASE("bsdf: conductor Fresnel") {
  // Normal incidence: ((eta - 1)^2 + k^2) / ((eta + 1)^2 + k^2) (Born & Wolf).
  float eta = 0.2004f, k = 3.9129f;
  CHECK(fresnel_complex(1.0f, eta, k) == doctest::Approx((sqr(eta - 1) + k * k) / (sqr(eta + 1) + k * k)).epsilon(1e-4).scale(1e-9));
  CHECK(fresnel_complex(0.0f, eta, k) == doctest::Approx(1.0f).epsilon(1e-4).scale(1e-9));
  // A conductor given by its reflectance colour reproduces it at normal incidence and goes to 1.
  Bsdf b = conductor_reflectance(Rgb(0.9f, 0.5f, 0.1f), 0.2f);
  Rgb f0 = bsdf_conductor_fresnel(b, 1.0f);
  CHECK(f0.x == doctest::Approx(0.9f).epsilon(1e-3).scale(1e-9));
  CHECK(f0.y == doctest::Approx(0.5f).epsilon(1e-3).scale(1e-9));
  CHECK(f0.z == doctest::Approx(0.1f).epsilon(1e-3).scale(1e-9));
  CHECK(bsdf_conductor_fresnel(b, 0.0f).z == doctest::Approx(1.0f).epsilon(1e-3).scale(1e-9));
  // Dielectric Fresnel from inside beyond the critical angle is total reflection.
  CHECK(fresnel_dielectric(-std::cos(50 * kPi / 180), 1.5f) == 1.0f);
}

TEST_CASE("bsdf: flags and roughness") {
  CHECK_FALSE(bsdf_is_delta(diffuse(Rgb(0.5f))));
  CHECK(bsdf_is_delta(conductor(0, 0)));
  CHECK(bsdf_is_delta(conductor(5e-4f, 9e-4f)));
  CHECK_FALSE(bsdf_is_delta(conductor(5e-4f, 0.2f)));
  CHECK(bsdf_roughness(diffuse(Rgb(0.5f))) == 1.0f);
  CHECK(bsdf_roughness(conductor(0.1f, 0.4f)) == doctest::Approx(0.2f));
  CHECK(is_black(bsdf_eval(conductor(0, 0), dir(10, 0), dir(10, 180))));
  CHECK(bsdf_pdf(conductor(0, 0), dir(10, 0), dir(10, 180)) == 0);
  // Diffuse is R / pi in the same hemisphere and zero across.
  CHECK(bsdf_eval(diffuse(Rgb(0.5f)), dir(10, 0), dir(50, 90)).x == doctest::Approx(0.5f / kPi));
  CHECK(is_black(bsdf_eval(diffuse(Rgb(0.5f)), dir(10, 0), dir(150, 90))));
}

TEST_CASE("bsdf: no NaN or Inf for any direction pair, grazing and z == 0 included") {
  std::vector<Bsdf> bs = {diffuse(Rgb(0.5f)), conductor(0, 0), conductor(0.05f, 0.05f), conductor(0.1f, 0.4f),
                          conductor(1e-4f, 0.5f), conductor_reflectance(Rgb(1), 0.3f), dielectric(1.5f, 0, 0),
                          dielectric(1.5f, 0.3f, 0.3f), dielectric(1.5f, 0.002f, 0.002f), dielectric(1.0f, 0.3f, 0.3f),
                          dielectric(1.00005f, 0, 0), dielectric(2.4f, 1.0f, 0.01f), coated(Rgb(0.5f), 1.5f, 0, 0),
                          coated(Rgb(0.5f), 1.5f, 0.3f, 0.3f), coated(Rgb(0), 1.5f, 0.002f, 0.002f), coated(Rgb(1), 1.0f, 0, 0),
                          coated(Rgb(1), 1.00005f, 0.3f, 0.3f), coated(Rgb(0.8f), 2.4f, 1e-4f, 0.5f), coated(Rgb(3), 1.5f, 1.0f, 1.0f),
                          coated(Rgb(0.5f), 0.7f, 0.2f, 0.2f)};
  std::vector<Vec3> special = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0.6f, 0.8f, 0},
                               {1, 0, 1e-7f}, {1, 0, -1e-7f}, {1e-8f, 0, 1}, {1e-30f, 0, 1}};
  for (Vec3& v : special) v = v / length(v);
  Pcg32 rng(33);
  for (int i = 0; i < 300; ++i) {
    Vec3 v = sample_uniform_sphere(rng.next_2d());
    if (i % 3 == 0) v.z *= 1e-4f;  // near-grazing
    special.push_back(normalize(v));
  }
  int bad = 0;
  for (const Bsdf& b : bs)
    for (Vec3 wo : special) {
      for (Vec3 wi : {special[size_t(rng.next_below(uint32_t(special.size())))], wo, -wo, Vec3{-wo.x, -wo.y, wo.z}}) {
        Rgb f = bsdf_eval(b, wo, wi);
        float pdf = bsdf_pdf(b, wo, wi);
        if (!is_finite(f) || !std::isfinite(pdf) || pdf < 0 || f.x < 0) {
          if (bad++ < 3) FAIL_CHECK("eval/pdf ", f.x, " ", pdf, " type ", int(b.type), " ax ", b.alpha_x, " wo ", wo.x, ",", wo.y, ",", wo.z, " wi ", wi.x, ",", wi.y, ",", wi.z);
        }
      }
      for (int j = 0; j < 20; ++j) {
        BsdfSample s;
        float ul = j == 0 ? 0.0f : rng.next_float();
        Vec2 u = j == 1 ? Vec2{0, 0} : (j == 2 ? Vec2{0x1.fffffep-1f, 0x1.fffffep-1f} : rng.next_2d());
        if (bsdf_sample(b, wo, ul, u, s)) {
          if (!is_finite(s.f) || !is_finite(s.wi) || !(s.pdf > 0) || !std::isfinite(s.pdf) || std::fabs(length(s.wi) - 1) > 1e-3f) {
            if (bad++ < 3) FAIL_CHECK("sample ", s.f.x, " ", s.pdf, " type ", int(b.type), " ax ", b.alpha_x, " wo ", wo.x, ",", wo.y, ",", wo.z, " wi ", s.wi.x, ",", s.wi.y, ",", s.wi.z);
          }
        }
      }
    }
  CHECK(bad == 0);
}

}  // TEST_SUITE

// The same chi-square tests with 10x the samples on a 4x finer grid: far more power against
// small pdf errors (e.g. a Jacobian wrong only at grazing angles). About 10 s in Release.
TEST_SUITE("slow") {
TEST_CASE("bsdf (slow): chi-square of every rough lobe with 2M samples on a 20x40 grid") {
  for (auto type : {Material::Type::diffuse, Material::Type::conductor, Material::Type::dielectric})
    chi2_cases(type, 1000 + 100 * uint64_t(type), 2000000, stat::SphereGrid{20, 40});
}
}  // TEST_SUITE
