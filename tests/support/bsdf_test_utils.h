// What the BSDF test files share (tests/scene/test_bsdf.cpp, test_bsdf_coated.cpp): directions in
// the shading frame by angles, and a prepared coated-diffuse BSDF.
#pragma once
#include <cmath>

#include "core/math.h"
#include "scene/bsdf.h"
#include "scene/coated.h"

namespace rl::test {

// The unit direction at polar angle theta and azimuth phi (degrees), +z = the shading normal.
inline Vec3 dir(float theta_deg, float phi_deg) {
  float t = theta_deg * kPi / 180, p = phi_deg * kPi / 180;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

// Coated diffuse with base reflectance r, coat index eta and GGX alphas (0: a smooth coat), its
// coat tables prepared as the scene loader prepares them.
inline Bsdf coated(Rgb r, float eta, float ax, float ay) {
  Material m;
  m.type = Material::Type::coated_diffuse;
  m.ior = eta;
  m.alpha_x = ax;
  m.alpha_y = ay;
  prepare_coated(m);
  return make_bsdf(m, r);
}

}  // namespace rl::test
