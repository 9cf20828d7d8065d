// coated_diffuse's coat terms by quadrature (coated.h; the model: bsdf_coated.h).
#include "scene/coated.h"

#include <cmath>
#include <vector>

#include "scene/microfacet.h"

namespace rl {

namespace {

// Gauss-Legendre nodes and weights on [a, b] (Newton on P_n from the Chebyshev guess; Press et
// al., Numerical Recipes 3rd ed., sec. 4.6.1, gauleg).
struct Quadrature {
  std::vector<double> x, w;
};
Quadrature gauss_legendre(int n, double a, double b) {
  Quadrature q{std::vector<double>(size_t(n)), std::vector<double>(size_t(n))};
  for (int i = 0; i < n; ++i) {
    double z = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 1;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1, p1 = 0;
      for (int j = 0; j < n; ++j) {
        const double p2 = p1;
        p1 = p0;
        p0 = ((2.0 * j + 1) * z * p1 - j * p2) / (j + 1);
      }
      dp = n * (z * p0 - p1) / (z * z - 1);
      const double dz = p0 / dp;
      z -= dz;
      if (std::fabs(dz) < 1e-15) break;
    }
    q.x[size_t(i)] = 0.5 * (a + b) - 0.5 * (b - a) * z;
    q.w[size_t(i)] = (b - a) / ((1 - z * z) * dp * dp);
  }
  return q;
}

Vec3 direction(double mu) {
  mu = std::min(1.0, std::max(mu, 1e-4));  // exactly grazing has no visible normals (Mitsuba: 1e-6)
  return Vec3{float(std::sqrt(1 - mu * mu)), 0.0f, float(mu)};
}

// ∫ g(m) D_w(m) dm over the visible normals from w, as a 2-D Gauss-Legendre rule on the unit square
// of Ggx::sample_visible (Heitz 2018): the map's Jacobian is the VNDF itself.
template <class G>
double over_visible_normals(const Ggx& ggx, Vec3 w, int n, const G& g) {
  static thread_local int cached_n = 0;
  static thread_local Quadrature q;
  if (cached_n != n) {
    q = gauss_legendre(n, 0, 1);
    cached_n = n;
  }
  double sum = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) sum += q.w[size_t(i)] * q.w[size_t(j)] * g(ggx.sample_visible(w, Vec2{float(q.x[size_t(i)]), float(q.x[size_t(j)])}));
  return sum;
}

bool smooth(float alpha) { return alpha < kSmoothAlpha; }

}  // namespace

double coat_transmittance(float eta, float alpha, double mu) {
  const Vec3 wo = direction(mu);
  if (smooth(alpha)) return 1 - fresnel_dielectric(wo.z, eta);
  const Ggx ggx{alpha, alpha};
  // Energy weight of a VNDF-sampled refraction: (1 - F) G2(wo, wt) / G1(wo) (bsdf_coated.h).
  return over_visible_normals(ggx, wo, 32, [&](Vec3 wm) {
    Vec3 wt;
    float etap;
    if (!refract(wo, wm, eta, &etap, &wt) || !(wt.z < 0)) return 0.0;
    return double((1 - fresnel_dielectric(dot(wo, wm), eta)) * ggx.g(wo, wt) / ggx.g1(wo));
  });
}

double coat_internal_albedo(float eta, float alpha, double mu) {
  const Vec3 wi = direction(mu);
  if (smooth(alpha)) return fresnel_dielectric(wi.z, 1 / eta);
  const Ggx ggx{alpha, alpha};
  // Reflection weight F G2(wi, wr) / G1(wi); 64 nodes: total internal reflection makes F kink.
  return over_visible_normals(ggx, wi, 64, [&](Vec3 wm) {
    const Vec3 wr = reflect(wi, wm);
    if (!(wr.z > 0)) return 0.0;
    return double(fresnel_dielectric(dot(wi, wm), 1 / eta) * ggx.g(wi, wr) / ggx.g1(wi));
  });
}

double coat_internal_reflectance(float eta, float alpha) {
  // Split at the critical angle of total internal reflection (a kink of E_int) when there is one.
  const double mu_c = eta > 1 ? std::sqrt(1 - 1 / (double(eta) * eta)) : 0.0;
  double sum = 0;
  for (auto [a, b] : {std::pair{0.0, mu_c}, std::pair{mu_c, 1.0}}) {
    if (!(b > a)) continue;
    const Quadrature q = gauss_legendre(smooth(alpha) ? 64 : 24, a, b);
    for (size_t i = 0; i < q.x.size(); ++i) sum += q.w[i] * coat_internal_albedo(eta, alpha, q.x[i]) * q.x[i];
  }
  return 2 * sum;
}

double fresnel_diffuse_reflectance(double n) {
  const double n2 = n * n, n4 = n2 * n2;
  auto sqr = [](double v) { return v * v; };
  return 0.5 + (n - 1) * (3 * n + 1) / (6 * (n + 1) * (n + 1)) +
         n2 * sqr(n2 - 1) / ((n2 + 1) * (n2 + 1) * (n2 + 1)) * std::log((n - 1) / (n + 1)) -
         2 * n * n2 * (n2 + 2 * n - 1) / ((n2 + 1) * (n4 - 1)) + 8 * n4 * (n4 + 1) / ((n2 + 1) * sqr(n4 - 1)) * std::log(n);
}

void prepare_coated(MaterialParams& m) {
  // The Bsdf's own smoothness test is on max(alpha_x, alpha_y), and make_bsdf clamps a rough
  // lobe's alphas to >= 1e-4 (bsdf_impl.h): an anisotropic coat with one near-zero axis is rough.
  const bool rough = std::max(m.alpha_x, m.alpha_y) >= kSmoothAlpha;
  const float a = rough ? std::sqrt(std::max(m.alpha_x, 1e-4f) * std::max(m.alpha_y, 1e-4f)) : 0.0f;
  for (int j = 0; j < kCoatTableSize; ++j) {
    const double mu = double(j * j) / double((kCoatTableSize - 1) * (kCoatTableSize - 1));
    const double t = j == 0 && !rough ? 0.0 : coat_transmittance(m.ior, a, mu);
    m.coat_t[j] = uint16_t(std::lround(std::min(1.0, std::max(0.0, t)) * 65535));
  }
  m.coat_fdr = float(coat_internal_reflectance(m.ior, a));
}

}  // namespace rl
