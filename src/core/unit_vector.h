// Unit vectors in fewer bytes: the octahedral map (Cigolle, Donow, Evangelakos, Mara, McGuire,
// Meyer 2014, "A Survey of Efficient Representations for Independent Unit Vectors", JCGT 3(2),
// §3.3-3.4), as compact G-buffers store normals (Falcor, RTXDI). The sphere is projected onto the
// octahedron |x| + |y| + |z| = 1 and the lower half folded over the upper one onto the square
// [-1, 1]^2: two numbers instead of three, spread almost evenly over the sphere.
//   oct_encode / oct_decode   two floats (8 bytes): back to within a few float ulps
//   OctSnorm16                two 16-bit signed normalized integers (4 bytes), rounded to the
//                             nearest of the four neighbouring grid points on the sphere
//                             ("oct32P", ibid. §3.4): at most 4.3e-5 radians off (test_unit_vector)
#pragma once
#include <cmath>
#include <cstdint>

#include "core/math.h"

namespace rl {

namespace unit_vector_detail {
RESTIR_HD inline float sign_not_zero(float v) { return v >= 0 ? 1.0f : -1.0f; }
// The fold of the lower hemisphere (ibid., Listing 1): its own inverse on the square's corners.
RESTIR_HD inline Vec2 fold(float x, float y) {
  return {(1 - std::fabs(y)) * sign_not_zero(x), (1 - std::fabs(x)) * sign_not_zero(y)};
}
}  // namespace unit_vector_detail

// The point of [-1, 1]^2 of unit vector n (n need not be exactly unit length).
RESTIR_HD inline Vec2 oct_encode(Vec3 n) {
  const float l1 = std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z);
  const float x = n.x / l1, y = n.y / l1;
  return n.z >= 0 ? Vec2{x, y} : unit_vector_detail::fold(x, y);
}
// The point of the octahedron of point e of [-1, 1]^2 (a vector of n's direction, not unit length).
// The fold without a branch (Stubbe's form): below the equator t = |x| + |y| - 1 > 0, and
// x - sign(x) t = sign(x) (1 - |y|), the fold's x; above it t = 0. A branch on the hemisphere was
// mispredicted for every other normal of a busy image and cost 4x the rest of the decode.
RESTIR_HD inline Vec3 oct_unfold(Vec2 e) {
  const float z = 1 - std::fabs(e.x) - std::fabs(e.y);
  const float t = z < 0 ? -z : 0.0f;  // (std::fmax is a library call here)
  return {e.x - std::copysign(t, e.x), e.y - std::copysign(t, e.y), z};
}
// The unit vector of point e of [-1, 1]^2.
RESTIR_HD inline Vec3 oct_decode(Vec2 e) { return normalize(oct_unfold(e)); }

// A unit vector in 4 bytes.
struct OctSnorm16 {
  int16_t x = 0, y = 0;
  RESTIR_HD static float to_float(int16_t q) { return float(q) * (1.0f / 32767.0f); }
  RESTIR_HD Vec3 decode() const { return oct_decode({to_float(x), to_float(y)}); }
  // Of the four grid points around n's octahedral point, the one that decodes nearest to n: the
  // smallest sin^2 of the angle, |v x n|^2 / (|v|^2 |n|^2) with v the unfolded grid point -- no
  // square root, and unlike the cosine (1 - 5e-9 at 1e-4 radians) resolved in float.
  RESTIR_HD static OctSnorm16 encode(Vec3 n) {
    const Vec2 e = oct_encode(n);
    const float fx = std::floor(e.x * 32767.0f), fy = std::floor(e.y * 32767.0f);
    OctSnorm16 best;
    float best_sin2 = kInfinity;
    for (int k = 0; k < 4; ++k) {
      const float qx = std::fmin(std::fmax(fx + float(k & 1), -32767.0f), 32767.0f);
      const float qy = std::fmin(std::fmax(fy + float(k >> 1), -32767.0f), 32767.0f);
      const OctSnorm16 c{int16_t(qx), int16_t(qy)};
      const Vec3 v = oct_unfold({to_float(c.x), to_float(c.y)});
      const Vec3 x = cross(v, n);
      const float sin2 = dot(x, x) / dot(v, v);  // x |n|^2, the same for all four
      if (sin2 < best_sin2) best = c, best_sin2 = sin2;
    }
    return best;
  }
};

}  // namespace rl
