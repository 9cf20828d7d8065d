// Coated diffuse (pbrt-v4's "coateddiffuse") as a DETERMINISTIC layered BSDF, so that ReSTIR's
// targets and shifts can evaluate it (pbrt-v4's own CoatedDiffuseBxDF is a stochastic random walk
// in the layer, whose f is only known in expectation). A dielectric coat (relative index
// eta = Bsdf::ior, GGX with the material's alphas; smooth below kSmoothAlpha) over a Lambertian base
// of albedo R, in the closed form of Weidlich & Wilkie 2007, "Arbitrarily layered micro-facet
// surfaces" (GRAPHITE), as Mitsuba writes it (Jakob, Mitsuba 3 src/bsdfs/roughplastic.cpp, and
// plastic.cpp for a smooth coat):
//
//   f(wo, wi) = F(wo.h) D(h) G2(wo, wi) / (4 |cos o| |cos i|)         the coat's GGX reflection
//             + T(cos i) T(cos o) R / (eta^2 pi (1 - R Fdr))           the base seen through the coat
//
// - F: dielectric Fresnel (PBR4 eq. 9.5); D, G2: GGX and the height-correlated Smith G2 (microfacet.h,
//   Heitz 2014 eq. 99; Mitsuba uses the separable G1 G1, a documented model difference).
// - T(mu): the coat's directional transmittance from outside -- the energy that enters the layer:
//   1 - F(mu) for a smooth coat; for a rough one the GGX transmission lobe integrated over the
//   visible normals, ∫ (1 - F(wo.m)) G2(wo, wt) / G1(wo) D_wo(m) dm (Walter 2007 eq. 21 with the
//   VNDF of Heitz 2018 eq. 2; Mitsuba's eval_transmittance), tabulated at load by coated.cpp.
// - Fdr: the coat's internal diffuse reflectance, 2 ∫ E_int(mu) mu dmu, E_int the reflection albedo
//   of the interface seen from inside (relative index 1/eta, total internal reflection included).
// - 1/eta^2: radiance leaving the denser layer spreads over a larger solid angle (PBR4 sec. 9.5.2).
// - R / (1 - R Fdr): the geometric series R Σ_k (R Fdr)^k of light bouncing between the base and
//   the coat's underside: Mitsuba's `nonlinear = true`. We use it rather than Mitsuba's default
//   R / (1 - Fdr) because it is what the layer's physics gives (pbrt-v4's random walk converges to
//   it, colour shift included: a saturated base gets more saturated); at R = 1 both forms agree, and
//   for a smooth coat the albedo is then exactly F + (1 - F) = 1, since eta^2 (1 - Fdr) = 1 - Fdr_ext.
// Not modelled (pbrt_materials.cpp says so): the layer's thickness and a medium in it (pbrt's
// albedo, g), and pbrt's random-walk knobs maxdepth / nsamples, which a closed form does not need.
// A rough coat's T table uses the isotropic alpha sqrt(alpha_x alpha_y); its lobe stays anisotropic.
//
// Sampling, Mitsuba's rule: the coat with probability P_c = (1 - T(cos o)) w / ((1 - T) w + T (1 - w)),
// w = 1 / (1 + mean R) (roughplastic's specular_sampling_weight, here from the local R), else the base
// by the cosine. A smooth coat's lobe is a delta (bsdf.h's conventions): eval/pdf exclude it, its
// sample is {mirror, F(cos o) / |cos i|, pdf P_c, is_delta}; the rest has pdf (1 - P_c) cos i / pi.
// A rough coat's sample carries the mixture pdf P_c D_wo(h) / (4 wo.h) + (1 - P_c) cos i / pi
// (VNDF reflection Jacobian, Walter 2007 eq. 14) and the full f (one-sample MIS over the two lobes).
// Two-sided like pbrt-v4's CoatedDiffuseBxDF: seen from below, everything is mirrored in z.
// Included by bsdf_impl.h only.
#pragma once

namespace rl {
namespace bsdf_detail {

// T(mu) from the table: nodes at mu_j = (j / (N-1))^2 (denser at grazing, where T falls fastest),
// linear in sqrt(mu) between them; unorm16 values (resolution 1.5e-5, half a float table's bytes).
RESTIR_HD inline float coat_table(const Bsdf& b, float mu) {
  const float x = std::sqrt(clamp(mu, 0.0f, 1.0f)) * float(kCoatTableSize - 1);
  const int i = std::min(int(x), kCoatTableSize - 2);
  return lerp(x - float(i), float(b.coat_t[i]), float(b.coat_t[i + 1])) * (1.0f / 65535.0f);
}

// The coat's transmittance T(mu) for mu = |cos| > 0 outside (file comment).
RESTIR_HD inline float coat_transmittance(const Bsdf& b, float mu) {
  if (is_smooth(b)) return 1 - fresnel_dielectric(mu, b.ior);
  return coat_table(b, mu);
}

// P_c, the probability of sampling the coat's lobe, from T(cos o) (file comment).
RESTIR_HD inline float coat_probability(const Bsdf& b, float t_o) {
  const float w = 1 / (1 + std::max(average(b.reflectance), 0.0f));
  const float c = (1 - t_o) * w, d = t_o * (1 - w);
  return c + d > 0 ? c / (c + d) : 0.0f;
}

// The base seen through the coat, without the cosine: T(cos i) T(cos o) R / (eta^2 pi (1 - R Fdr)).
RESTIR_HD inline Rgb coat_base(const Bsdf& b, float t_i, float t_o) {
  const Rgb r = max(b.reflectance, Rgb(0));
  const Rgb den = max(Rgb(1) - r * b.coat_fdr, Rgb(1e-6f));  // > 0 for R <= 1 (Fdr < 1); textures may exceed 1
  return r / den * (t_i * t_o * kInvPi / sqr(b.ior));
}

// The rough coat's GGX reflection for wo, wi in the upper hemisphere (as dielectric_eval's).
RESTIR_HD inline float coat_specular(const Bsdf& b, Vec3 wo, Vec3 wi) {
  Vec3 wm = wo + wi;
  if (!(length_squared(wm) > 0)) return 0;
  wm = normalize(wm);
  const Ggx m = ggx_of(b);
  const float F = fresnel_dielectric(dot(wo, wm), b.ior);
  return finite_or_zero(m.d(wm) * m.g(wo, wi) * F / (4 * wo.z * wi.z));
}

RESTIR_HD inline Rgb coated_eval(const Bsdf& b, Vec3 wo, Vec3 wi) {
  if (!same_hemisphere(wo, wi)) return Rgb(0);
  if (wo.z < 0) {  // two-sided: mirror both into the upper hemisphere
    wo.z = -wo.z;
    wi.z = -wi.z;
  }
  Rgb f = coat_base(b, coat_transmittance(b, wi.z), coat_transmittance(b, wo.z));
  if (!is_smooth(b)) f += Rgb(coat_specular(b, wo, wi));
  return finite_or_zero(f);
}

RESTIR_HD inline float coated_pdf(const Bsdf& b, Vec3 wo, Vec3 wi) {
  if (!same_hemisphere(wo, wi)) return 0;
  if (wo.z < 0) {
    wo.z = -wo.z;
    wi.z = -wi.z;
  }
  const float pc = coat_probability(b, coat_transmittance(b, wo.z));
  float pdf = (1 - pc) * wi.z * kInvPi;
  if (!is_smooth(b) && pc > 0) {
    const Vec3 wm = normalize(wo + wi);
    const float dom = dot(wo, wm);
    if (dom > 0) pdf += pc * ggx_of(b).d_visible(wo, wm) / (4 * dom);
  }
  return finite_or_zero(pdf);
}

RESTIR_HD inline bool coated_sample(const Bsdf& b, Vec3 wo, float u_lobe, Vec2 u, BsdfSample& out) {
  if (wo.z == 0) return false;
  const float side = wo.z < 0 ? -1.0f : 1.0f;
  const Vec3 wo_up{wo.x, wo.y, wo.z * side};
  const float t_o = coat_transmittance(b, wo_up.z), pc = coat_probability(b, t_o);
  Vec3 wi;
  if (u_lobe < pc) {
    if (is_smooth(b)) {  // the coat's mirror, a delta of weight F(cos o) = 1 - T(cos o) (PBR4 eq. 9.9)
      wi = Vec3{-wo.x, -wo.y, wo.z};
      out = {wi, Rgb((1 - t_o) / std::fabs(wi.z)), pc, true};
      return 1 - t_o > 0;
    }
    wi = reflect(wo_up, ggx_of(b).sample_visible(wo_up, u));
  } else {
    wi = sample_cosine_hemisphere(u);
  }
  if (!(wi.z > 0) || !unit_ok(wi)) return false;
  wi.z *= side;
  out = {wi, coated_eval(b, wo, wi), coated_pdf(b, wo, wi), false};
  return out.pdf > 0;
}

}  // namespace bsdf_detail
}  // namespace rl
