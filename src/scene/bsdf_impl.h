// The BSDF bodies (bsdf.h's functions), inline and RESTIR_HD so that the CUDA backend compiles
// the same code. Our own code, following the semantics of pbrt-v4's DiffuseBxDF, ConductorBxDF
// and DielectricBxDF (Pharr, Jakob, Humphreys, PBR 4th ed., ch. 9); coated diffuse in
// bsdf_coated.h. Included by bsdf.h only.
#pragma once
#include "core/sampling.h"
#include "scene/microfacet.h"

namespace rl {


namespace bsdf_detail {

RESTIR_HD inline bool same_hemisphere(Vec3 a, Vec3 b) { return a.z * b.z > 0; }
RESTIR_HD inline Rgb finite_or_zero(Rgb v) { return is_finite(v) ? v : Rgb(0); }
RESTIR_HD inline float finite_or_zero(float v) { return std::isfinite(v) ? v : 0.0f; }
RESTIR_HD inline bool unit_ok(Vec3 w) { return is_finite(w) && length_squared(w) > 0.5f; }

RESTIR_HD inline Ggx ggx_of(const Bsdf& b) { return {b.alpha_x, b.alpha_y}; }
RESTIR_HD inline bool is_smooth(const Bsdf& b) { return std::max(b.alpha_x, b.alpha_y) < kSmoothAlpha; }
RESTIR_HD inline bool index_matched(const Bsdf& b) { return !(b.ior > 1.0001f || b.ior < 1 / 1.0001f); }

// ---------------------------------------------------------------- diffuse (Lambert)
// f = R / pi; cosine-weighted sampling, pdf = |cos wi| / pi (Malley's method, PBR4 sec. 9.2).
RESTIR_HD inline Rgb diffuse_eval(const Bsdf& b, Vec3 wo, Vec3 wi) {
  if (!same_hemisphere(wo, wi)) return Rgb(0);
  return b.reflectance * kInvPi;
}
RESTIR_HD inline float diffuse_pdf(Vec3 wo, Vec3 wi) {
  if (!same_hemisphere(wo, wi)) return 0;
  return std::fabs(wi.z) * kInvPi;
}
RESTIR_HD inline bool diffuse_sample(const Bsdf& b, Vec3 wo, Vec2 u, BsdfSample& out) {
  if (wo.z == 0) return false;
  Vec3 wi = sample_cosine_hemisphere(u);
  if (wo.z < 0) wi.z = -wi.z;
  if (wi.z == 0) return false;
  out = {wi, b.reflectance * kInvPi, std::fabs(wi.z) * kInvPi, false};
  return true;
}

// ---------------------------------------------------------------- conductor
// Torrance-Sparrow / Cook-Torrance: f = D(wm) F(wo.wm) G2(wo, wi) / (4 |cos o| |cos i|)
// (Walter 2007 eq. 20; PBR4 eq. 9.33). VNDF sampling: pdf = D_wo(wm) / (4 |wo.wm|), the
// reflection Jacobian |dwm/dwi| = 1 / (4 |wi.wm|) (Walter 2007 eq. 14; Heitz 2018 eq. 17).
RESTIR_HD inline Rgb conductor_eval(const Bsdf& b, Vec3 wo, Vec3 wi) {
  if (is_smooth(b) || !same_hemisphere(wo, wi)) return Rgb(0);
  float co = std::fabs(wo.z), ci = std::fabs(wi.z);
  if (co == 0 || ci == 0) return Rgb(0);
  Vec3 wm = wi + wo;
  if (length_squared(wm) == 0) return Rgb(0);
  wm = face_forward(normalize(wm), Vec3{0, 0, 1});
  Ggx m = ggx_of(b);
  Rgb F = bsdf_conductor_fresnel(b, abs_dot(wo, wm));
  return finite_or_zero(F * (m.d(wm) * m.g(wo, wi) / (4 * co * ci)));
}
RESTIR_HD inline float conductor_pdf(const Bsdf& b, Vec3 wo, Vec3 wi) {
  if (is_smooth(b) || !same_hemisphere(wo, wi)) return 0;
  Vec3 wm = wo + wi;
  if (length_squared(wm) == 0) return 0;
  wm = face_forward(normalize(wm), Vec3{0, 0, 1});
  float dom = abs_dot(wo, wm);
  if (dom == 0) return 0;
  return finite_or_zero(ggx_of(b).d_visible(wo, wm) / (4 * dom));
}
RESTIR_HD inline bool conductor_sample(const Bsdf& b, Vec3 wo, Vec2 u, BsdfSample& out) {
  if (wo.z == 0) return false;
  if (is_smooth(b)) {
    // Perfect mirror: weight F(cos o); the delta's f is F / |cos i| (PBR4 eq. 9.9).
    Vec3 wi{-wo.x, -wo.y, wo.z};
    float ci = std::fabs(wi.z);
    out = {wi, bsdf_conductor_fresnel(b, ci) / ci, 1.0f, true};
    return is_finite(out.f);
  }
  Ggx m = ggx_of(b);
  Vec3 wm = m.sample_visible(wo, u);
  Vec3 wi = reflect(wo, wm);
  if (!same_hemisphere(wo, wi) || !unit_ok(wi)) return false;
  float dom = abs_dot(wo, wm);
  if (dom == 0) return false;
  float pdf = m.d_visible(wo, wm) / (4 * dom);
  float co = std::fabs(wo.z), ci = std::fabs(wi.z);
  if (co == 0 || ci == 0 || !(pdf > 0) || !std::isfinite(pdf)) return false;
  Rgb F = bsdf_conductor_fresnel(b, dom);
  out = {wi, finite_or_zero(F * (m.d(wm) * m.g(wo, wi) / (4 * co * ci))), pdf, false};
  return true;
}

// ---------------------------------------------------------------- dielectric
// Smooth: Fresnel-weighted choice between the mirror and the refracted delta (PBR4 sec. 9.5).
// Rough: Walter et al. 2007 with the generalized half vector wm = normalize(wo + eta' wi)
// (Walter eq. 16), reflection f = D F G / (4 |cos o cos i|) (eq. 20) and transmission
// f = D (1-F) G |wi.wm| |wo.wm| / (|cos i| |cos o| (wi.wm + wo.wm / eta')^2) / eta'^2 (eq. 21,
// written with eta' = eta_i / eta_o as in PBR4 eq. 9.40, radiance scaled by 1/eta'^2). Transmission
// Jacobian |dwm/dwi| = |wi.wm| / (wi.wm + wo.wm / eta')^2 (Walter eq. 17; PBR4 eq. 9.37).

// Generalized half vector and the "reflect" flag; false when the configuration is degenerate or
// uses a back-facing microfacet (PBR4 DielectricBxDF::f).
RESTIR_HD inline bool dielectric_half(const Bsdf& b, Vec3 wo, Vec3 wi, Vec3& wm, bool& reflect_lobe, float& etap) {
  float co = wo.z, ci = wi.z;
  reflect_lobe = co * ci > 0;
  etap = 1;
  if (!reflect_lobe) etap = co > 0 ? b.ior : 1 / b.ior;
  wm = wi * etap + wo;
  if (ci == 0 || co == 0 || !(length_squared(wm) > 0)) return false;
  wm = face_forward(normalize(wm), Vec3{0, 0, 1});
  if (dot(wm, wi) * ci < 0 || dot(wm, wo) * co < 0) return false;
  return unit_ok(wm);
}

RESTIR_HD inline Rgb dielectric_eval(const Bsdf& b, Vec3 wo, Vec3 wi) {
  if (index_matched(b) || is_smooth(b)) return Rgb(0);
  Vec3 wm;
  bool refl;
  float etap;
  if (!dielectric_half(b, wo, wi, wm, refl, etap)) return Rgb(0);
  Ggx m = ggx_of(b);
  float F = fresnel_dielectric(dot(wo, wm), b.ior);
  if (refl) return Rgb(finite_or_zero(m.d(wm) * m.g(wo, wi) * F / std::fabs(4 * wi.z * wo.z)));
  float denom = sqr(dot(wi, wm) + dot(wo, wm) / etap) * wi.z * wo.z;
  if (denom == 0) return Rgb(0);
  float ft = m.d(wm) * (1 - F) * m.g(wo, wi) * std::fabs(dot(wi, wm) * dot(wo, wm) / denom) / sqr(etap);
  return Rgb(finite_or_zero(ft));
}

RESTIR_HD inline float dielectric_pdf(const Bsdf& b, Vec3 wo, Vec3 wi) {
  if (index_matched(b) || is_smooth(b)) return 0;
  Vec3 wm;
  bool refl;
  float etap;
  if (!dielectric_half(b, wo, wi, wm, refl, etap)) return 0;
  Ggx m = ggx_of(b);
  float R = fresnel_dielectric(dot(wo, wm), b.ior), T = 1 - R;
  if (!(R + T > 0)) return 0;
  float pdf;
  if (refl) {
    pdf = m.d_visible(wo, wm) / (4 * abs_dot(wo, wm)) * R / (R + T);
  } else {
    float denom = sqr(dot(wi, wm) + dot(wo, wm) / etap);
    if (denom == 0) return 0;
    pdf = m.d_visible(wo, wm) * abs_dot(wi, wm) / denom * T / (R + T);
  }
  return finite_or_zero(pdf);
}

RESTIR_HD inline bool dielectric_sample(const Bsdf& b, Vec3 wo, float u_lobe, Vec2 u, BsdfSample& out) {
  if (wo.z == 0) return false;
  if (index_matched(b)) {  // no interface: light passes straight through (PBR4, eta == 1)
    Vec3 wi = -wo;
    out = {wi, Rgb(1.0f / std::fabs(wi.z)), 1.0f, true};
    return true;
  }
  if (is_smooth(b)) {
    float R = fresnel_dielectric(wo.z, b.ior), T = 1 - R;
    if (u_lobe < R / (R + T)) {
      Vec3 wi{-wo.x, -wo.y, wo.z};
      out = {wi, Rgb(R / std::fabs(wi.z)), R / (R + T), true};
      return true;
    }
    Vec3 wi;
    float etap;
    if (!refract(wo, Vec3{0, 0, 1}, b.ior, &etap, &wi) || wi.z == 0) return false;
    out = {wi, Rgb(T / std::fabs(wi.z) / sqr(etap)), T / (R + T), true};
    return is_finite(out.f) && out.pdf > 0;
  }
  Ggx m = ggx_of(b);
  Vec3 wm = m.sample_visible(wo, u);
  float R = fresnel_dielectric(dot(wo, wm), b.ior), T = 1 - R;
  if (u_lobe < R / (R + T)) {
    Vec3 wi = reflect(wo, wm);
    if (!same_hemisphere(wo, wi) || !unit_ok(wi)) return false;
    float pdf = m.d_visible(wo, wm) / (4 * abs_dot(wo, wm)) * R / (R + T);
    float f = m.d(wm) * m.g(wo, wi) * R / std::fabs(4 * wi.z * wo.z);
    if (!(pdf > 0) || !std::isfinite(pdf) || !std::isfinite(f)) return false;
    out = {wi, Rgb(f), pdf, false};
    return true;
  }
  Vec3 wi;
  float etap;
  if (!refract(wo, wm, b.ior, &etap, &wi)) return false;  // total internal reflection
  if (same_hemisphere(wo, wi) || wi.z == 0 || !unit_ok(wi)) return false;
  float denom = sqr(dot(wi, wm) + dot(wo, wm) / etap);
  if (denom == 0) return false;
  float pdf = m.d_visible(wo, wm) * abs_dot(wi, wm) / denom * T / (R + T);
  float ft = T * m.d(wm) * m.g(wo, wi) * std::fabs(dot(wi, wm) * dot(wo, wm) / (wi.z * wo.z * denom)) / sqr(etap);
  if (!(pdf > 0) || !std::isfinite(pdf) || !std::isfinite(ft)) return false;
  out = {wi, Rgb(ft), pdf, false};
  return true;
}

}  // namespace bsdf_detail

}  // namespace rl

#include "scene/bsdf_coated.h"

namespace rl {

RESTIR_HD inline Bsdf make_bsdf(const MaterialParams& m, Rgb reflectance) {
  Bsdf b;
  b.type = m.type;
  b.reflectance = reflectance;
  b.eta = m.eta;
  b.k = m.k;
  b.use_reflectance = m.use_reflectance;
  b.ior = std::isfinite(m.ior) && m.ior > 0 ? m.ior : 1.0f;
  b.alpha_x = std::isfinite(m.alpha_x) ? std::max(m.alpha_x, 0.0f) : 0.0f;
  b.alpha_y = std::isfinite(m.alpha_y) ? std::max(m.alpha_y, 0.0f) : 0.0f;
  if (std::max(b.alpha_x, b.alpha_y) >= kSmoothAlpha) {
    b.alpha_x = std::max(b.alpha_x, 1e-4f);
    b.alpha_y = std::max(b.alpha_y, 1e-4f);
  }
  if (m.type == Material::Type::coated_diffuse) {
    b.coat_fdr = m.coat_fdr;
    for (int i = 0; i < kCoatTableSize; ++i) b.coat_t[i] = m.coat_t[i];
  }
  return b;
}

RESTIR_HD inline Rgb bsdf_conductor_fresnel(const Bsdf& b, float cos_i) {
  if (b.use_reflectance) {
    // pbrt-v4 ConductorMaterial with "reflectance": eta = 1, k = 2 sqrt(r) / sqrt(1 - r), which
    // makes the exact complex Fresnel equal r at normal incidence: k^2 / (4 + k^2) = r.
    Rgb r = min(max(b.reflectance, Rgb(0)), Rgb(0.9999f));
    Rgb k{2 * std::sqrt(r.x / (1 - r.x)), 2 * std::sqrt(r.y / (1 - r.y)), 2 * std::sqrt(r.z / (1 - r.z))};
    return fresnel_complex(cos_i, Rgb(1), k);
  }
  return fresnel_complex(cos_i, b.eta, b.k);
}

RESTIR_HD inline Rgb bsdf_eval(const Bsdf& b, Vec3 wo, Vec3 wi) {
  switch (b.type) {
    case Material::Type::diffuse: return bsdf_detail::diffuse_eval(b, wo, wi);
    case Material::Type::conductor: return bsdf_detail::conductor_eval(b, wo, wi);
    case Material::Type::dielectric: return bsdf_detail::dielectric_eval(b, wo, wi);
    case Material::Type::coated_diffuse: return bsdf_detail::coated_eval(b, wo, wi);
  }
  return Rgb(0);
}

RESTIR_HD inline float bsdf_pdf(const Bsdf& b, Vec3 wo, Vec3 wi) {
  switch (b.type) {
    case Material::Type::diffuse: return bsdf_detail::diffuse_pdf(wo, wi);
    case Material::Type::conductor: return bsdf_detail::conductor_pdf(b, wo, wi);
    case Material::Type::dielectric: return bsdf_detail::dielectric_pdf(b, wo, wi);
    case Material::Type::coated_diffuse: return bsdf_detail::coated_pdf(b, wo, wi);
  }
  return 0;
}

RESTIR_HD inline bool bsdf_sample(const Bsdf& b, Vec3 wo, float u_lobe, Vec2 u, BsdfSample& out) {
  out = {};
  bool ok = false;
  switch (b.type) {
    case Material::Type::diffuse: ok = bsdf_detail::diffuse_sample(b, wo, u, out); break;
    case Material::Type::conductor: ok = bsdf_detail::conductor_sample(b, wo, u, out); break;
    case Material::Type::dielectric: ok = bsdf_detail::dielectric_sample(b, wo, u_lobe, u, out); break;
    case Material::Type::coated_diffuse: ok = bsdf_detail::coated_sample(b, wo, u_lobe, u, out); break;
  }
  if (!ok || !bsdf_detail::unit_ok(out.wi) || !is_finite(out.f) || !(out.pdf > 0) || !std::isfinite(out.pdf)) {
    out = {};
    return false;
  }
  return true;
}

RESTIR_HD inline bool bsdf_is_delta(const Bsdf& b) {
  switch (b.type) {
    case Material::Type::diffuse: return false;
    case Material::Type::conductor: return bsdf_detail::is_smooth(b);
    case Material::Type::dielectric: return bsdf_detail::is_smooth(b) || bsdf_detail::index_matched(b);
    case Material::Type::coated_diffuse: return false;  // the base is never a delta
  }
  return false;
}

RESTIR_HD inline bool bsdf_has_delta(const Bsdf& b) {
  // An index-matched smooth coat reflects nothing (F = 0): no delta lobe to sample.
  if (b.type == Material::Type::coated_diffuse) return bsdf_detail::is_smooth(b) && !bsdf_detail::index_matched(b);
  return bsdf_is_delta(b);
}

RESTIR_HD inline bool bsdf_delta_lobe(const Bsdf& b, Vec3 wo, BsdfSample& out) {
  out = {};
  if (b.type != Material::Type::coated_diffuse || !bsdf_has_delta(b) || wo.z == 0) return false;
  const Vec3 wi{-wo.x, -wo.y, wo.z};  // the coat's mirror, weight F(cos o) (bsdf_coated.h)
  out = {wi, Rgb(fresnel_dielectric(std::fabs(wo.z), b.ior) / std::fabs(wi.z)), 1.0f, true};
  return is_finite(out.f);
}

RESTIR_HD inline float bsdf_roughness(const Bsdf& b) {
  if (b.type == Material::Type::diffuse) return 1.0f;
  // A smooth coat's only non-delta lobe is the diffuse base.
  if (b.type == Material::Type::coated_diffuse && bsdf_detail::is_smooth(b)) return 1.0f;
  return std::sqrt(b.alpha_x * b.alpha_y);
}

}  // namespace rl
