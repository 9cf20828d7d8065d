// Direction sampling at a path vertex, shared by the path tracer and ReSTIR PT so that random
// replay regenerates exactly the directions of the walk: the BSDF's own importance sampling, or
// (bsdf_sampling = false, the thesis' fig. 4.7 toggle) the cosine-weighted hemisphere on wo's side
// — both sides with probability 1/2 for transmissive materials. BSDFs with a delta lobe (delta
// BSDFs, a smooth coat) can only be sampled by the BSDF: the cosine would never find the delta.
#pragma once
#include "core/sampling.h"
#include "scene/bsdf.h"

namespace rl {

RESTIR_HD inline bool sample_direction(const Bsdf& bsdf, bool use_bsdf, Vec3 wo, float u_lobe, Vec2 u, BsdfSample& s) {
  if (use_bsdf || bsdf_has_delta(bsdf)) return bsdf_sample(bsdf, wo, u_lobe, u, s);
  const bool transmissive = bsdf.type == Material::Type::dielectric;
  Vec3 wi = sample_cosine_hemisphere(u);
  float side = wo.z < 0 ? -1.0f : 1.0f;
  float pdf = cosine_hemisphere_pdf(wi.z);
  if (transmissive) {
    pdf *= 0.5f;
    if (u_lobe < 0.5f) side = -side;
  }
  wi.z *= side;
  if (pdf <= 0) return false;
  s.wi = wi;
  s.f = bsdf_eval(bsdf, wo, wi);
  s.pdf = pdf;
  s.is_delta = false;
  return true;
}

// Solid-angle density of sample_direction() (0 for delta BSDFs; the non-delta lobes' for a mix).
RESTIR_HD inline float direction_pdf(const Bsdf& bsdf, bool use_bsdf, Vec3 wo, Vec3 wi) {
  if (use_bsdf || bsdf_has_delta(bsdf)) return bsdf_pdf(bsdf, wo, wi);
  float pdf = cosine_hemisphere_pdf(std::fabs(wi.z));
  if (bsdf.type == Material::Type::dielectric) return 0.5f * pdf;
  return (wo.z < 0) == (wi.z < 0) ? pdf : 0.0f;
}

}  // namespace rl
