// Device-shaped views of a Scene (ARCHITECTURE.md, "Backends"): flat, trivially copyable structs
// of pointers and counts that per-sample code reads on the host and, with the pointers replaced
// by device copies (src/backends/cuda), on the GPU. SceneViewData owns the small per-mesh /
// per-texture tables and points into the Scene's own arrays, so the Scene must outlive it and
// must not be reallocated while it is in use (animate_scene moves vertices in place).
#pragma once
#include <cstdint>
#include <vector>

#include "core/math.h"
#include "scene/ray_queries.h"
#include "scene/scene.h"

namespace rl {

struct ImageView {
  const Rgb* pixels = nullptr;  // row-major, row 0 at the top
  int width = 0, height = 0;
  RESTIR_HD const Rgb& at(int x, int y) const { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
  RESTIR_HD bool empty() const { return pixels == nullptr || width <= 0 || height <= 0; }
};
inline ImageView image_view(const Image& img) { return {img.empty() ? nullptr : img.pixels.data(), img.width, img.height}; }

struct TextureView {
  TextureParams params;
  ImageView image;
};

struct MeshView {
  const Vec3* positions = nullptr;
  const Vec3* normals = nullptr;    // null: no shading normals
  const Vec2* uvs = nullptr;        // null: no uvs
  const uint32_t* indices = nullptr;
  uint32_t vertex_count = 0, triangle_count = 0;
  int material = 0;
  bool flip_normal = false;
  int animation = -1;               // index into Scene::animations (-1: static)
};

struct SphereView {
  Vec3 center;
  float radius = 1;
  int material = 0;
  bool flip_normal = false;
  int animation = -1;
};

struct SceneView {
  const MeshView* meshes = nullptr;
  const SphereView* spheres = nullptr;
  const MaterialParams* materials = nullptr;
  const TextureView* textures = nullptr;
  uint32_t mesh_count = 0, sphere_count = 0, material_count = 0, texture_count = 0;
  RESTIR_HD uint32_t sphere_geom() const { return mesh_count; }  // Hit::geom of spheres (as Accel)
};

// Everything shading needs about a hit point.
struct SurfaceInteraction {
  Vec3 p;
  Vec3 ng;        // geometric normal, orientation as pbrt (flip_normal applied), unit
  Vec3 ns;        // shading normal (interpolated N, on the same side as ng), unit
  Vec2 uv;
  int material = 0;
  bool is_sphere = false;
  uint32_t geom = kInvalidId, prim = kInvalidId;
  Vec2 barycentrics;  // of vertices 1 and 2 (triangles): with geom and prim, what rebuilds the rest (surface_at)
};

// The host tables behind a SceneView of `scene` (its arrays are pointed to, not copied).
struct SceneViewData {
  std::vector<MeshView> meshes;
  std::vector<SphereView> spheres;
  std::vector<MaterialParams> materials;
  std::vector<TextureView> textures;
  SceneViewData() = default;
  explicit SceneViewData(const Scene& scene);
  SceneView view() const {
    return {meshes.data(), spheres.data(), materials.data(), textures.data(), uint32_t(meshes.size()),
            uint32_t(spheres.size()), uint32_t(materials.size()), uint32_t(textures.size())};
  }
};

// Texture value at uv: bilinear lookup with repeat wrapping for images (v = 0 at the image's
// bottom row, as pbrt), checkerboard in uv cells.
RESTIR_HD inline Rgb eval_texture(const TextureParams& tex, const ImageView& img, Vec2 uv) {
  const float u = uv.x * tex.uscale + tex.udelta, v = uv.y * tex.vscale + tex.vdelta;
  // Coordinates beyond +-2^24 carry no sub-texel precision, and their conversion to int would
  // overflow (and a NaN convert differently on host and device): such lookups take the base value.
  if (!(std::fabs(u) < 16777216.0f) || !(std::fabs(v) < 16777216.0f)) return tex.value;
  switch (tex.kind) {
    case TextureParams::Kind::constant:
      return tex.value;
    case TextureParams::Kind::checkerboard: {
      const int cu = int(std::floor(u)), cv = int(std::floor(v));
      return ((cu + cv) & 1) == 0 ? tex.tex1 : tex.tex2;
    }
    case TextureParams::Kind::image: {
      if (img.empty()) return tex.value;
      auto texel = [&](int x, int y) -> const Rgb& {  // repeat wrapping
        x %= img.width, y %= img.height;
        if (x < 0) x += img.width;
        if (y < 0) y += img.height;
        return img.at(x, y);
      };
      // Bilinear filtering on texel centres; image row 0 is the top (v = 1).
      const float x = u * float(img.width) - 0.5f, y = (1 - v) * float(img.height) - 0.5f;
      if (!(std::fabs(x) < 2e9f) || !(std::fabs(y) < 2e9f)) return tex.value;  // int range (see above)
      const float fx = std::floor(x), fy = std::floor(y);
      const int x0 = int(fx), y0 = int(fy);
      const float dx = x - fx, dy = y - fy;
      return (1 - dx) * (1 - dy) * texel(x0, y0) + dx * (1 - dy) * texel(x0 + 1, y0) + (1 - dx) * dy * texel(x0, y0 + 1) +
             dx * dy * texel(x0 + 1, y0 + 1);
    }
  }
  return tex.value;
}

// A material's reflectance at a hit: its texture if it has one, else its constant.
RESTIR_HD inline Rgb material_reflectance(const SceneView& s, const MaterialParams& m, Vec2 uv) {
  if (m.reflectance_texture < 0 || uint32_t(m.reflectance_texture) >= s.texture_count) return m.reflectance;
  const TextureView& t = s.textures[m.reflectance_texture];
  return eval_texture(t.params, t.image, uv);
}

// A point p on sphere `prim` as shading sees it. The normal is p's own direction from the centre
// (not the ray's hit before surface_interaction projected it onto the sphere), so that the point
// alone rebuilds the same bits (surface_at: ReSTIR PT's reconnection vertex keeps only the point).
RESTIR_HD inline SurfaceInteraction sphere_surface(const SceneView& scene, uint32_t prim, Vec3 p) {
  SurfaceInteraction si;
  si.geom = scene.sphere_geom();
  si.prim = prim;
  const SphereView& s = scene.spheres[prim];
  const Vec3 n = normalize(p - s.center);
  si.p = p;
  si.ng = s.flip_normal ? -n : n;
  si.ns = si.ng;
  // pbrt's sphere (u, v): phi / 2pi and theta from the z axis; only textured spheres need it
  // (the trigonometry is a measurable share of a frame on sphere-lit scenes).
  if (scene.materials[s.material].reflectance_texture >= 0) {
    float phi = std::atan2(n.y, n.x);
    if (phi < 0) phi += 2 * kPi;
    si.uv = {phi * kInv2Pi, std::acos(clamp(n.z, -1.0f, 1.0f)) * kInvPi};
  }
  si.material = s.material;
  si.is_sphere = true;
  return si;
}

// Triangle `prim` of mesh `geom` at barycentrics (b1, b2) as shading sees it; a degenerate
// triangle (no normal) gets `fallback` as its geometric normal.
RESTIR_HD inline SurfaceInteraction triangle_surface(const SceneView& scene, uint32_t geom, uint32_t prim, Vec2 b, Vec3 fallback) {
  SurfaceInteraction si;
  si.geom = geom;
  si.prim = prim;
  si.barycentrics = b;
  const MeshView& m = scene.meshes[geom];
  const uint32_t i0 = m.indices[3 * prim], i1 = m.indices[3 * prim + 1], i2 = m.indices[3 * prim + 2];
  const float b1 = b.x, b2 = b.y, b0 = 1 - b1 - b2;
  si.p = m.positions[i0] * b0 + m.positions[i1] * b1 + m.positions[i2] * b2;
  Vec3 ng = triangle_normal(m.positions, m.normals, m.indices, m.flip_normal, prim);
  if (is_black(ng)) ng = fallback;
  si.ng = ng;
  if (m.normals) {
    const Vec3 ns = m.normals[i0] * b0 + m.normals[i1] * b1 + m.normals[i2] * b2;
    const float l = length(ns);
    si.ns = l > 0 ? face_forward(ns / l, ng) : ng;
  } else {
    si.ns = ng;
  }
  si.uv = m.uvs ? m.uvs[i0] * b0 + m.uvs[i1] * b1 + m.uvs[i2] * b2 : Vec2{b1, b2};
  si.material = m.material;
  return si;
}

// The hit point of `ray` (its closest hit `hit`) as shading sees it.
RESTIR_HD inline SurfaceInteraction surface_interaction(const SceneView& scene, const Ray& ray, const Hit& hit) {
  if (hit.geom == scene.sphere_geom()) {
    const SphereView& s = scene.spheres[hit.prim];
    const Vec3 n = normalize(ray.o + ray.d * hit.t - s.center);
    return sphere_surface(scene, hit.prim, s.center + n * s.radius);  // projected onto the surface to cut the hit's float error
  }
  return triangle_surface(scene, hit.geom, hit.prim, Vec2{hit.u, hit.v}, -ray.d);  // degenerate: any consistent normal
}

// A surface point again from what identifies it -- its geometry, primitive, barycentrics (a
// triangle) and point (a sphere) -- with the bits surface_interaction gave the hit that found it
// (-ffp-contract=off: the same expressions round the same way wherever they are inlined). false
// for a degenerate triangle, whose normal surface_interaction took from the ray, which is not kept.
RESTIR_HD inline bool surface_at(const SceneView& scene, uint32_t geom, uint32_t prim, Vec2 barycentrics, Vec3 p, SurfaceInteraction& si) {
  if (geom == scene.sphere_geom()) {
    si = sphere_surface(scene, prim, p);
    return true;
  }
  si = triangle_surface(scene, geom, prim, barycentrics, Vec3(0));
  return !is_black(si.ng);
}

}  // namespace rl
