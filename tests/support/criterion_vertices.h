// Hand-made path vertices and BSDFs for the tests of the hybrid shift's reconnection criteria
// (integrators/restir_pt/path_terms.h: the footprints, the roughness proxy).
#pragma once
#include "integrators/restir_pt/walk.h"

namespace rl::test {

// A vertex at p with geometric and shading normal n, seen from direction wo, with BSDF b.
inline pt_detail::Vertex vertex(Vec3 p, Vec3 n, Vec3 wo, const Bsdf& b) {
  pt_detail::Vertex v;
  v.p = p;
  v.ng = n;
  v.frame = Frame::from_normal(n);
  v.wo = wo;
  v.bsdf = b;
  v.delta = bsdf_is_delta(b);
  return v;
}

// A BSDF of the given type with isotropic GGX alpha (0: smooth), reflectance 0.9.
inline Bsdf ggx_bsdf(Material::Type type, float alpha) {
  MaterialParams m;
  m.type = type;
  m.alpha_x = m.alpha_y = alpha;
  return make_bsdf(m, Rgb(0.9f));
}
inline Bsdf conductor(float alpha) { return ggx_bsdf(Material::Type::conductor, alpha); }

}  // namespace rl::test
