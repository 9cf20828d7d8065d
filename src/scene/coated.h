// Host-side precomputation of coated_diffuse's coat terms (the model: bsdf_coated.h): the coat's
// transmittance table T(mu) and internal diffuse reflectance Fdr, by Gauss-Legendre quadrature
// over the GGX visible normals (as Mitsuba 3's eval_transmittance / eval_reflectance,
// include/mitsuba/render/microfacet.h), with our height-correlated G2.
#pragma once
#include "scene/scene.h"

namespace rl {

// Fills m.coat_t and m.coat_fdr from m.ior and m.alpha_x / alpha_y (a rough coat's table uses the
// isotropic alpha sqrt(alpha_x alpha_y)). Every coated_diffuse material must pass through it before
// a Bsdf is made from it (the pbrt loader does, at load); a few ms per material.
void prepare_coated(MaterialParams& m);

// The quadratures behind it (tests compare them with independent integrations). alpha below
// kSmoothAlpha means a smooth coat (closed-form Fresnel).
// T(mu): the fraction of the energy arriving from outside at cos theta = mu that enters the coat.
double coat_transmittance(float eta, float alpha, double mu);
// E_int(mu): reflection albedo of the interface seen from inside (relative index 1/eta).
double coat_internal_albedo(float eta, float alpha, double mu);
// Fdr = 2 ∫ E_int(mu) mu dmu.
double coat_internal_reflectance(float eta, float alpha);

// Closed form of the hemispherical-cosine average of the smooth dielectric Fresnel reflectance
// seen from outside, Fdr_ext = 2 ∫ F(mu, eta) mu dmu for eta > 1 (unpolarized; Walsh 1926, as
// quoted e.g. by Egan & Hilgeman 1973; d'Eon 2016, "A Hitchhiker's Guide to Multiple Scattering").
double fresnel_diffuse_reflectance(double eta);

}  // namespace rl
