// Materials resolved at a hit point: evaluation, sampling and pdf of the BSDF (pbrt-v4 semantics:
// DiffuseBxDF, ConductorBxDF, DielectricBxDF, radiance transport; pbrt-v4's coateddiffuse as a
// deterministic layered model, bsdf_coated.h).
//
// Conventions
// - All directions are in the local shading frame (+z = shading normal) and point AWAY from the
//   surface. wo may be in the lower hemisphere (inside a dielectric, or the back of a surface).
// - Diffuse, conductor and coated diffuse are two-sided like pbrt-v4 (non-zero only when wo and wi lie in the same
//   hemisphere; sampling mirrors to wo's side). Called with wo.z > 0 they reflect into z > 0 only.
// - bsdf_eval returns f WITHOUT the cosine; bsdf_pdf is the solid-angle pdf of bsdf_sample.
// - Delta lobes: bsdf_eval/bsdf_pdf return 0; bsdf_sample returns is_delta, f = weight / |cos wi|
//   and pdf = the discrete probability of choosing that lobe, so f |cos wi| / pdf is the throughput.
// - A BSDF may mix a delta lobe with non-delta ones (coated diffuse with a smooth coat):
//   bsdf_is_delta is false, bsdf_has_delta true, eval/pdf cover the non-delta lobes only (pdf
//   times their lobe probability) and a sample's is_delta says which kind of lobe produced it.
//   Code that reuses a sampled direction (reconnection, MIS) must look at the sample's is_delta.
// - Refraction scales radiance by 1/eta^2 (radiance transport, PBR4 sec. 9.5.2).
// - No function returns NaN/Inf, for any pair of directions (grazing and z == 0 included).
#pragma once
#include "core/math.h"
#include "scene/scene.h"

namespace rl {

struct Bsdf {                      // resolved at a hit point from a Material (+ texture lookup)
  Material::Type type = Material::Type::diffuse;
  Rgb reflectance{0.5f};           // diffuse albedo, or conductor normal-incidence colour if use_reflectance
  Rgb eta{1}, k{0};
  bool use_reflectance = false;
  float ior = 1.5f;                // dielectric (outside medium is 1); <= 1.0001 = index-matched, passes straight through
  float alpha_x = 0, alpha_y = 0;  // GGX; both < 1e-3 => treated as perfectly smooth (delta)
  float coat_fdr = 0;              // coated diffuse: MaterialParams::coat_fdr / coat_t (bsdf_coated.h)
  uint16_t coat_t[kCoatTableSize] = {};
};

// reflectance = texture value or m.reflectance. Rough alphas are clamped to >= 1e-4 on both axes
// (pbrt-v4: an anisotropic lobe with one near-zero axis makes D blow up).
RESTIR_HD inline Bsdf make_bsdf(const MaterialParams& m, Rgb reflectance);

struct BsdfSample {
  Vec3 wi;
  Rgb f;          // WITHOUT the cosine; for delta lobes the delta's weight / |cos wi|
  float pdf = 0;  // solid angle, or the lobe probability for delta lobes
  bool is_delta = false;
};

RESTIR_HD inline Rgb bsdf_eval(const Bsdf&, Vec3 wo, Vec3 wi);    // 0 for delta lobes
RESTIR_HD inline float bsdf_pdf(const Bsdf&, Vec3 wo, Vec3 wi);   // solid-angle pdf of bsdf_sample; 0 for delta lobes
// u_lobe picks reflection vs transmission (dielectric), u the direction. false = no sample.
RESTIR_HD inline bool bsdf_sample(const Bsdf&, Vec3 wo, float u_lobe, Vec2 u, BsdfSample& out);
// The delta lobe of a BSDF that mixes one with non-delta lobes (bsdf_has_delta, not bsdf_is_delta:
// a smooth coat) as a whole: its direction, f = its weight / |cos wi|, pdf 1 (no lobe choice), for
// estimators that add the delta's part deterministically. false when there is none.
RESTIR_HD inline bool bsdf_delta_lobe(const Bsdf&, Vec3 wo, BsdfSample& out);
RESTIR_HD inline bool bsdf_is_delta(const Bsdf&);                 // every lobe is a delta (smooth conductor/dielectric)
RESTIR_HD inline bool bsdf_has_delta(const Bsdf&);                // some lobe is a delta (the above, and a smooth coat)
// Roughness of the sharpest NON-delta lobe: 1 for diffuse, sqrt(alpha_x*alpha_y) for GGX lobes; a
// coated diffuse with a smooth coat has the diffuse base (1), with a rough coat the coat's alpha.
// Delta lobes are told apart per sample (BsdfSample::is_delta), not by this number.
RESTIR_HD inline float bsdf_roughness(const Bsdf&);

// Conductor Fresnel term actually used (exact complex Fresnel; with use_reflectance the colour r
// is turned into eta = 1, k = 2 sqrt(r / (1 - r)) so that F(0) = r exactly, as pbrt-v4 does).
RESTIR_HD inline Rgb bsdf_conductor_fresnel(const Bsdf&, float cos_i);

}  // namespace rl

#include "scene/bsdf_impl.h"
