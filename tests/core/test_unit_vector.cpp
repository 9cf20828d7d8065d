// Octahedral unit vectors (core/unit_vector.h), what the compact G-buffer stores its normals and
// view direction in: the float map back to within a few ulps, the 16-bit one within its grid's
// bound, everywhere on the sphere -- the poles, the equator the fold meets, the axes, random points.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/rng.h"
#include "core/sampling.h"
#include "core/unit_vector.h"

using namespace rl;

namespace {

// Directions that stress the map: the six axes, the octahedron's edges and faces, points just
// above and below the equator (where the lower half is folded), and uniform random directions.
std::vector<Vec3> test_directions() {
  std::vector<Vec3> d;
  for (int a = 0; a < 3; ++a)
    for (float s : {1.0f, -1.0f}) {
      Vec3 v(0);
      (a == 0 ? v.x : a == 1 ? v.y : v.z) = s;
      d.push_back(v);
    }
  for (float x : {-1.0f, -0.5f, 0.0f, 0.5f, 1.0f})
    for (float y : {-1.0f, -0.5f, 0.0f, 0.5f, 1.0f})
      for (float z : {-1.0f, -1e-6f, 0.0f, 1e-6f, 1.0f})
        if (x != 0 || y != 0 || z != 0) d.push_back(normalize(Vec3{x, y, z}));
  Pcg32 rng(5, 17);
  for (int i = 0; i < 200000; ++i) d.push_back(sample_uniform_sphere(rng.next_2d()));
  return d;
}

double angle(Vec3 a, Vec3 b) { return std::atan2(double(length(cross(a, b))), double(dot(a, b))); }

}  // namespace

TEST_SUITE("unit_vector") {
  TEST_CASE("two floats give the direction back to a few ulps, unit length, on every side") {
    double worst = 0, worst_length = 0;
    for (const Vec3 n : test_directions()) {
      const Vec2 e = oct_encode(n);
      REQUIRE(std::fabs(e.x) <= 1.0f);
      REQUIRE(std::fabs(e.y) <= 1.0f);
      const Vec3 back = oct_decode(e);
      worst = std::max(worst, angle(n, back));
      worst_length = std::max(worst_length, std::fabs(double(length(back)) - 1.0));
      if (std::fabs(n.z) > 1e-5f) REQUIRE((back.z > 0) == (n.z > 0));  // the fold keeps the hemisphere
    }
    MESSAGE("float octahedral map: largest angle " << worst << " rad");
    CHECK(worst < 1e-6);
    CHECK(worst_length < 1e-6);
  }

  TEST_CASE("16 bits a component: within the grid's bound, and the nearest of the four grid points") {
    double worst = 0, worst_floor = 0;
    for (const Vec3 n : test_directions()) {
      const OctSnorm16 q = OctSnorm16::encode(n);
      worst = std::max(worst, angle(n, q.decode()));
      // Rounding toward the lower-left grid point alone (a planted weaker encoder) is worse.
      const Vec2 e = oct_encode(n);
      const OctSnorm16 f{int16_t(std::floor(e.x * 32767.0f)), int16_t(std::floor(e.y * 32767.0f))};
      worst_floor = std::max(worst_floor, angle(n, f.decode()));
      // (ties within 1%: sin^2 of nearly parallel vectors is resolved to about that in float)
      REQUIRE(length(q.decode() - n) <= length(f.decode() - n) * 1.01f);
    }
    MESSAGE("16-bit octahedral map: largest angle " << worst << " rad (floor only: " << worst_floor << ")");
    // The grid step is 1 / 32767 in the square (half a diagonal: 2.2e-5), which the map stretches
    // up to ~2x on the sphere.
    CHECK(worst < 5e-5);
    CHECK(worst_floor > 2 * worst);
  }
}
