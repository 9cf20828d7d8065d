// pbrt-v4's disk and bilinearmesh shapes: area, orientation (pbrt's normal rule), uv, transforms.
#include <cmath>

#include "loader_test_utils.h"

using namespace rl;
using namespace rl::loader_test;

namespace {
double area(const TriangleMesh& m) {
  double a = 0;
  for (size_t t = 0; t < m.indices.size() / 3; ++t) {
    const Vec3 p0 = m.positions[m.indices[3 * t]], p1 = m.positions[m.indices[3 * t + 1]], p2 = m.positions[m.indices[3 * t + 2]];
    a += 0.5 * double(length(cross(p1 - p0, p2 - p0)));
  }
  return a;
}
// Every non-degenerate triangle's normal (pbrt's rule through triangle_normal) along `n`.
bool all_facing(const TriangleMesh& m, Vec3 n) {
  for (uint32_t t = 0; t < m.indices.size() / 3; ++t) {
    const Vec3 g = triangle_normal(m, t);
    if (length(g) > 0 && !(dot(g, n) > 0.999f)) return false;
  }
  return true;
}
}  // namespace

TEST_SUITE("loaders") {

TEST_CASE("pbrt: disk - area within 1e-4, normal +z (flipped by ReverseOrientation), annulus and partial") {
  Scene s = load_text(kWorld + "Translate 0 0 2\nShape \"disk\" \"float radius\" [2] \"float height\" [0.5]\n");
  REQUIRE(s.meshes.size() == 1);
  const TriangleMesh& m = s.meshes[0];
  CHECK(area(m) == doctest::Approx(kPi * 4).epsilon(1e-4));
  CHECK(all_facing(m, Vec3(0, 0, 1)));
  for (const Vec3& p : m.positions) CHECK(p.z == doctest::Approx(2.5f));
  Scene r = load_text(kWorld + "ReverseOrientation\nShape \"disk\"\n");
  CHECK(all_facing(r.meshes[0], Vec3(0, 0, -1)));
  Scene a = load_text(kWorld + "Shape \"disk\" \"float radius\" [1] \"float innerradius\" [0.5] \"float phimax\" [180]\n");
  CHECK(area(a.meshes[0]) == doctest::Approx(0.5 * kPi * (1 - 0.25)).epsilon(1e-4));
  for (const Vec3& p : a.meshes[0].positions) CHECK(p.y >= -1e-6f);
  CHECK(all_facing(a.meshes[0], Vec3(0, 0, 1)));
  // Rotated 90 degrees about x: +z goes to -y.
  Scene x = load_text(kWorld + "Rotate 90 1 0 0\nShape \"disk\"\n");
  CHECK(all_facing(x.meshes[0], Vec3(0, -1, 0)));
  CHECK(error_of(kWorld + "Shape \"disk\" \"float radius\" [1] \"float innerradius\" [1]\n").find("innerradius") != std::string::npos);
  CHECK(error_of(kWorld + "Shape \"disk\" \"float radius\" [-1]\n").find("radius") != std::string::npos);
}

TEST_CASE("pbrt: bilinearmesh - a planar patch is two triangles, a curved one follows p(u, v)") {
  // p00, p10, p01, p11 as pbrt orders them: dpdu x dpdv = +z.
  Scene s = load_text(kWorld + "Shape \"bilinearmesh\" \"point3 P\" [0 0 0  2 0 0  0 3 0  2 3 0]\n");
  REQUIRE(s.meshes.size() == 1);
  CHECK(s.meshes[0].indices.size() == 6);
  CHECK(area(s.meshes[0]) == doctest::Approx(6.0));
  CHECK(all_facing(s.meshes[0], Vec3(0, 0, 1)));
  // A hyperbolic paraboloid z = u v over the unit square: its area is known in closed form,
  // integral of sqrt(1 + u^2 + v^2) = 1.28079; the 16 x 16 tessellation is within 0.1%.
  Scene c = load_text(kWorld + "Shape \"bilinearmesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0  1 1 1] \"integer indices\" [0 1 2 3]\n");
  CHECK(c.meshes[0].indices.size() == 16 * 16 * 6);
  CHECK(area(c.meshes[0]) == doctest::Approx(1.28079).epsilon(1e-3));
  for (const Vec3& p : c.meshes[0].positions) CHECK(p.z == doctest::Approx(p.x * p.y).epsilon(1e-5));
  CHECK(error_of(kWorld + "Shape \"bilinearmesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0  1 1 0] \"integer indices\" [0 1 2]\n")
            .find("4 per patch") != std::string::npos);
  CHECK(error_of(kWorld + "Shape \"bilinearmesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0  1 1 0] \"integer indices\" [0 1 2 7]\n")
            .find("out of range") != std::string::npos);
}

TEST_CASE("pbrt: a misspelt directive or parameter names the closest one") {
  CHECK(error_of(kWorld + "Shpae \"sphere\"\n").find("unknown directive 'Shpae' (did you mean 'Shape'?)") != std::string::npos);
  CHECK(error_of(kWorld + "Shape \"disk\" \"float raduis\" [2]\n").find("(did you mean 'radius'?)") != std::string::npos);
  CHECK(error_of(kWorld + "Shape \"sphere\" \"float zzzzzz\" [2]\n").find("did you mean") == std::string::npos);
  // A parameter the reader knows but does not use names no suggestion (once: "did you mean 'power'?").
  const std::string power = error_of(kWorld + "LightSource \"point\" \"float power\" [2]\n");
  CHECK(power.find("\"float power\"") != std::string::npos);
  CHECK(power.find("not supported") != std::string::npos);
  CHECK(power.find("did you mean") == std::string::npos);
}

}  // TEST_SUITE
