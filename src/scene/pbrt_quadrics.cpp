// pbrt-v4's "disk" and "bilinearmesh" shapes, as triangle meshes (see pbrt_parser.cpp). Both keep
// pbrt-v4's orientation: the triangles wind so that cross(p1 - p0, p2 - p0) is the shape's own
// normal (the disk's object-space +z, a patch's dpdu x dpdv), and make_world_mesh applies the
// transform and ReverseOrientation as it does for "trianglemesh" (pbrt flips all of them by
// reverseOrientation ^ transformSwapsHandedness).
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "scene/pbrt_parser.h"

namespace rl::pbrt {

namespace {
constexpr float kPi = 3.14159265358979323846f;
}

// pbrt-v4 Disk: radius 1, innerradius 0, height 0, phimax 360; the points (r cos phi, r sin phi,
// height) for r in [innerradius, radius], phi in [0, phimax]; uv = (phi / phimax, (radius - r) /
// (radius - innerradius)). Tessellated into 256 sectors per full turn: the polygon's area is the
// disk's within 1e-4 (1 - sin t / t, t = 2 pi / 256), and so is an emitting disk's power.
TriangleMesh Parser::disk_shape(const Token& d, const ParamList& pl, const Mat4& xf) {
  pl.check_range("radius", 0, HUGE_VAL, true);
  pl.check_range("innerradius", 0);
  pl.check_range("phimax", 0, 360, true);
  const float r = pl.get_float("radius", 1), ri = pl.get_float("innerradius", 0), h = pl.get_float("height", 0);
  const float phimax = pl.get_float("phimax", 360) * kPi / 180;
  if (!std::isfinite(h)) pl.find("height")->fail("must be finite");
  if (!(ri < r)) pl.find("innerradius")->fail(fmt::format("must be less than the radius {}", r));
  pl.check_unused("Shape \"disk\"");
  const int sectors = std::max(3, int(std::ceil(256 * phimax / (2 * kPi))));
  std::vector<Vec3> P;
  std::vector<Vec2> uv;
  std::vector<uint32_t> idx;
  for (int i = 0; i <= sectors; ++i) {  // two rings: outer (v = 0) and inner (v = 1)
    const float u = float(i) / float(sectors), phi = u * phimax;
    P.push_back(Vec3(r * std::cos(phi), r * std::sin(phi), h));
    uv.push_back(Vec2(u, 0));
    P.push_back(Vec3(ri * std::cos(phi), ri * std::sin(phi), h));
    uv.push_back(Vec2(u, 1));
  }
  for (uint32_t i = 0; i < uint32_t(sectors); ++i) {
    const uint32_t o0 = 2 * i, i0 = 2 * i + 1, o1 = 2 * i + 2, i1 = 2 * i + 3;
    idx.insert(idx.end(), {i0, o0, o1});                      // counter-clockwise seen from +z
    if (ri > 0) idx.insert(idx.end(), {i0, o1, i1});          // the annulus' second triangle
  }
  return detail::make_world_mesh(P, {}, uv, idx, xf, gs_.reverse);
}

// pbrt-v4 BilinearPatchMesh: 4 indices per patch (p00, p10, p01, p11), optional "normal N" and
// "point2 uv" per vertex (default uv: the patch's (u, v)). A planar patch is two triangles (exact);
// a curved one is a 16 x 16 grid of the bilinear surface p(u, v), normals and uv interpolated alike.
TriangleMesh Parser::bilinear_mesh_shape(const Token& d, const ParamList& pl, const Mat4& xf) {
  const std::vector<Vec3> P = pl.get_point3s("P");
  if (P.empty()) d.fail("bilinearmesh: missing \"point3 P\"");
  std::vector<int> ix = pl.get_ints("indices");
  if (ix.empty()) {
    if (P.size() != 4) d.fail("bilinearmesh: \"integer indices\" required unless there are exactly 4 vertices");
    ix = {0, 1, 2, 3};
  }
  if (ix.size() % 4 != 0) pl.find("indices")->fail(fmt::format("{} indices: expected 4 per patch", ix.size()));
  for (int i : ix)
    if (i < 0 || size_t(i) >= P.size())
      pl.find("indices")->fail(fmt::format("vertex index {} is out of range [0, {}]", i, P.size() - 1));
  const std::vector<Vec3> N = pl.get_normals("N");
  const std::vector<Vec2> UV = pl.get_point2s("uv");
  if (!N.empty() && N.size() != P.size()) pl.find("N")->fail(fmt::format("{} normals for {} vertices", N.size(), P.size()));
  if (!UV.empty() && UV.size() != P.size()) pl.find("uv")->fail(fmt::format("{} uvs for {} vertices", UV.size(), P.size()));
  pl.check_unused("Shape \"bilinearmesh\"");
  std::vector<Vec3> op, on;
  std::vector<Vec2> ouv;
  std::vector<uint32_t> idx;
  auto bilerp = [](auto a00, auto a10, auto a01, auto a11, float u, float v) {
    return (a00 * (1 - u) + a10 * u) * (1 - v) + (a01 * (1 - u) + a11 * u) * v;
  };
  for (size_t p = 0; p < ix.size(); p += 4) {
    const int c[4] = {ix[p], ix[p + 1], ix[p + 2], ix[p + 3]};
    const Vec3 e = P[c[1]] - P[c[0]], f = P[c[2]] - P[c[0]], g = P[c[3]] - P[c[0]];
    const float scale = std::max({length(e), length(f), length(g), 1e-30f});
    const bool planar = std::fabs(dot(cross(e, f), g)) <= 1e-5f * scale * scale * scale;
    const int n = planar ? 1 : 16;
    const uint32_t base = uint32_t(op.size());
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        const float u = float(i) / float(n), v = float(j) / float(n);
        op.push_back(bilerp(P[c[0]], P[c[1]], P[c[2]], P[c[3]], u, v));
        if (!N.empty()) on.push_back(normalize(bilerp(N[c[0]], N[c[1]], N[c[2]], N[c[3]], u, v)));
        const Vec2 t = UV.empty() ? Vec2(u, v) : Vec2(bilerp(UV[c[0]].x, UV[c[1]].x, UV[c[2]].x, UV[c[3]].x, u, v),
                                                      bilerp(UV[c[0]].y, UV[c[1]].y, UV[c[2]].y, UV[c[3]].y, u, v));
        ouv.push_back(t);
      }
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const uint32_t a = base + uint32_t(j * (n + 1) + i), b = a + 1, cc = a + uint32_t(n + 1), dd = cc + 1;
        idx.insert(idx.end(), {a, b, cc, b, dd, cc});  // cross(p10 - p00, p01 - p00): pbrt's dpdu x dpdv
      }
  }
  return detail::make_world_mesh(op, on, ouv, idx, xf, gs_.reverse);
}

}  // namespace rl::pbrt
