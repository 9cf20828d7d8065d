// Microfacet and Fresnel helpers shared by the BSDFs (and their tests). Local shading frame:
// +z is the shading normal; every direction is a unit vector pointing away from the surface.
//
// Distribution: anisotropic GGX / Trowbridge-Reitz (Trowbridge & Reitz 1975; Walter et al. 2007,
// "Microfacet Models for Refraction through Rough Surfaces", eq. 33; anisotropic form from
// Heitz 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs", eq. 85).
// Masking-shadowing: the HEIGHT-CORRELATED Smith G2 = 1 / (1 + Lambda(wo) + Lambda(wi))
// (Heitz 2014, eq. 99), with the GGX Lambda of Heitz 2014 eq. 86. This is what pbrt-v4 uses.
// Sampling: distribution of visible normals (Heitz 2018, "Sampling the GGX Distribution of
// Visible Normals", JCGT 7(4), listing 1), pdf D_w(wm) = G1(w) max(0, w.wm) D(wm) / w.z
// (Heitz 2018 eq. 2 / Heitz & d'Eon 2014 eq. 2).
#pragma once

#include "core/math.h"
#include "core/sampling.h"

namespace rl {

// Below this roughness (both axes) the surface is treated as perfectly smooth (pbrt-v4's
// TrowbridgeReitzDistribution::EffectivelySmooth).
inline constexpr float kSmoothAlpha = 1e-3f;

struct Ggx {
  float ax = 0, ay = 0;

  RESTIR_HD bool effectively_smooth() const { return std::max(ax, ay) < kSmoothAlpha; }

  // D(wm) for unit wm = 1 / (pi ax ay (x^2/ax^2 + y^2/ay^2 + z^2)^2): the trig-free form of
  // Walter 2007 eq. 33 / Heitz 2014 eq. 85; wm.z <= 0 has no microfacets.
  RESTIR_HD float d(Vec3 wm) const {
    if (!(wm.z > 0)) return 0;
    float e = sqr(wm.x / ax) + sqr(wm.y / ay) + sqr(wm.z);
    float v = 1.0f / (kPi * ax * ay * e * e);
    return std::isfinite(v) ? v : 0.0f;
  }
  // Smith Lambda for GGX (Heitz 2014 eq. 86): (-1 + sqrt(1 + alpha_o^2 tan^2 theta)) / 2 with the
  // projected roughness alpha_o^2 = ax^2 cos^2 phi + ay^2 sin^2 phi (eq. 80).
  RESTIR_HD float lambda(Vec3 w) const {
    float z2 = w.z * w.z;
    if (z2 == 0) return kInfinity;
    float a2t2 = (sqr(ax * w.x) + sqr(ay * w.y)) / z2;
    if (!std::isfinite(a2t2)) return kInfinity;
    return 0.5f * (std::sqrt(1 + a2t2) - 1);
  }
  // Smith masking G1 = 1 / (1 + Lambda) (Heitz 2014 eq. 43).
  RESTIR_HD float g1(Vec3 w) const { return 1.0f / (1.0f + lambda(w)); }
  // Height-correlated masking-shadowing (Heitz 2014 eq. 99).
  RESTIR_HD float g(Vec3 wo, Vec3 wi) const { return 1.0f / (1.0f + lambda(wo) + lambda(wi)); }

  // Density of visible normals seen from w (Heitz 2018 eq. 2), with |.| so that w may lie in the
  // lower hemisphere (then the normals visible from -w are meant, as in pbrt-v4).
  RESTIR_HD float d_visible(Vec3 w, Vec3 wm) const {
    float cw = std::fabs(w.z);
    if (cw == 0) return 0;
    float v = g1(w) / cw * d(wm) * abs_dot(w, wm);
    return std::isfinite(v) ? v : 0.0f;
  }

  // Heitz 2018, listing 1: stretch, sample the projected hemisphere, unstretch. w in the lower
  // hemisphere is mirrored to the upper one (pbrt-v4 Sample_wm). Returns a unit wm with wm.z > 0.
  RESTIR_HD Vec3 sample_visible(Vec3 w, Vec2 u) const {
    Vec3 wh = normalize(Vec3{ax * w.x, ay * w.y, w.z});
    if (wh.z < 0) wh = -wh;
    Vec3 t1 = wh.z < 0.99999f ? normalize(cross(Vec3{0, 0, 1}, wh)) : Vec3{1, 0, 0};
    Vec3 t2 = cross(wh, t1);
    Vec2 p = sample_uniform_disk_concentric(u);
    float h = safe_sqrt(1 - p.x * p.x);
    float s = 0.5f * (1 + wh.z);
    float py = lerp(s, h, p.y);  // (1 - s) * h + s * p.y
    float pz = safe_sqrt(1 - p.x * p.x - py * py);
    Vec3 nh = t1 * p.x + t2 * py + wh * pz;
    return normalize(Vec3{ax * nh.x, ay * nh.y, std::max(1e-6f, nh.z)});
  }
};

// Unpolarized Fresnel reflectance of a dielectric interface (Born & Wolf; pbrt-v4 FrDielectric,
// PBR4 eq. 9.5): eta = eta_t / eta_i of the side cos_i > 0 faces; cos_i < 0 swaps the sides.
// Total internal reflection returns 1.
RESTIR_HD inline float fresnel_dielectric(float cos_i, float eta) {
  cos_i = clamp(cos_i, -1.0f, 1.0f);
  if (cos_i < 0) {
    eta = 1 / eta;
    cos_i = -cos_i;
  }
  float sin2_i = 1 - cos_i * cos_i;
  float sin2_t = sin2_i / (eta * eta);
  if (sin2_t >= 1) return 1.0f;
  float cos_t = safe_sqrt(1 - sin2_t);
  float r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  float r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return 0.5f * (r_parl * r_parl + r_perp * r_perp);
}

// Fresnel reflectance of a conductor with complex IOR eta + i k seen from vacuum. The same value
// as pbrt-v4's FrComplex (PBR4 eq. 9.6 with complex eta), written in real arithmetic as pbrt-v3's
// FrConductor (PBR3 sec. 8.2.1; Born & Wolf): std::complex division and sqrt cost more than the
// ray queries on conductor-heavy scenes. One wavelength (RGB channel) at a time.
RESTIR_HD inline float fresnel_complex(float cos_i, float eta, float k) {
  cos_i = clamp(cos_i, 0.0f, 1.0f);
  const float cos2 = cos_i * cos_i, sin2 = 1 - cos2;
  const float eta2 = eta * eta, k2 = k * k;
  const float t0 = eta2 - k2 - sin2;
  const float a2_plus_b2 = std::sqrt(std::max(t0 * t0 + 4 * eta2 * k2, 0.0f));
  const float t1 = a2_plus_b2 + cos2;
  const float a = safe_sqrt(0.5f * (a2_plus_b2 + t0));
  const float t2 = 2 * cos_i * a;
  const float rs = (t1 - t2) / (t1 + t2);
  const float t3 = cos2 * a2_plus_b2 + sin2 * sin2;
  const float t4 = t2 * sin2;
  const float rp = rs * (t3 - t4) / (t3 + t4);
  const float r = 0.5f * (rp + rs);
  return std::isfinite(r) ? clamp(r, 0.0f, 1.0f) : 1.0f;
}
RESTIR_HD inline Rgb fresnel_complex(float cos_i, Rgb eta, Rgb k) {
  return {fresnel_complex(cos_i, eta.x, k.x), fresnel_complex(cos_i, eta.y, k.y), fresnel_complex(cos_i, eta.z, k.z)};
}

// Refraction of wi about n (both pointing away from the surface, n on wi's side or not); eta is
// eta_t / eta_i for wi on n's side. Returns false on total internal reflection; etap receives
// the relative IOR actually used (pbrt-v4 Refract, PBR4 eq. 9.4 / Snell's law).
RESTIR_HD inline bool refract(Vec3 wi, Vec3 n, float eta, float* etap, Vec3* wt) {
  float cos_i = dot(n, wi);
  if (cos_i < 0) {
    eta = 1 / eta;
    cos_i = -cos_i;
    n = -n;
  }
  float sin2_i = std::max(0.0f, 1 - cos_i * cos_i);
  float sin2_t = sin2_i / (eta * eta);
  if (sin2_t >= 1) return false;
  float cos_t = safe_sqrt(1 - sin2_t);
  *wt = -wi / eta + (cos_i / eta - cos_t) * n;
  if (etap) *etap = eta;
  return true;
}

}  // namespace rl
