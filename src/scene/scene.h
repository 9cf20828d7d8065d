// The renderer's scene: world-space geometry, materials, lights and the camera (with its animation).
// Filled by the loaders (pbrt-v4, OBJ, glTF, PLY); knows nothing about integrators or ReSTIR.
#pragma once
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/math.h"
#include "image/image.h"
#include "scene/animation.h"

namespace rl {

// Largest world coordinate (and sphere radius) a scene may use. Embree asserts on ray origins
// beyond ~1.8e18 and float arithmetic on 1e30 overflows in squared distances; 1e12 is far beyond
// any scene (a planet in millimetres) and keeps every product finite.
inline constexpr float kMaxWorldCoordinate = 1e12f;

// A texture's parameters (what device code reads; the image travels separately, texture_view.h).
struct TextureParams {
  enum class Kind { constant, image, checkerboard };
  Kind kind = Kind::constant;
  Rgb value{1};                 // constant (and an image texture's value when its image is empty)
  Rgb tex1{1}, tex2{0};         // checkerboard colours
  float uscale = 1, vscale = 1, udelta = 0, vdelta = 0;  // uv mapping
};

// A texture: constant, an image map (bilinear, repeat), or a checkerboard in uv.
struct Texture : TextureParams {
  Image image;                  // image (linear RGB; 8-bit files are decoded from sRGB)
  std::string name;
};

// Material parameters as written in the scene; a Bsdf is resolved from them at each hit. The
// plain part (MaterialParams) is what device code reads.
// Size of a coated material's coat transmittance table (scene/coated.h).
inline constexpr int kCoatTableSize = 16;

struct MaterialParams {
  enum class Type { diffuse, conductor, dielectric, coated_diffuse };
  Type type = Type::diffuse;
  Rgb reflectance{0.5f};        // diffuse (and coated_diffuse base) albedo; conductor: if use_reflectance, the normal-incidence colour
  int reflectance_texture = -1; // index into Scene::textures, overrides reflectance
  Rgb eta{0.2004f, 0.9240f, 1.1022f};  // conductor complex IOR (default: copper, as pbrt-v4)
  Rgb k{3.9129f, 2.4528f, 2.1422f};
  bool use_reflectance = false; // conductor given by "reflectance" instead of eta/k
  float ior = 1.5f;             // dielectric (or coated_diffuse's coat) index of refraction (outside medium is 1)
  float alpha_x = 0, alpha_y = 0;  // GGX roughness (already remapped if remaproughness was set); 0 = smooth
  // coated_diffuse only, filled on the host by prepare_coated (scene/coated.h) from ior and the
  // alphas: the coat's internal diffuse reflectance and its transmittance table (unorm16).
  float coat_fdr = 0;
  uint16_t coat_t[kCoatTableSize] = {};
};
struct Material : MaterialParams {
  std::string name;
};

// Emission attached to a shape (pbrt "AreaLightSource diffuse").
struct AreaEmission {
  Rgb radiance{0};     // L, scale already applied
  bool two_sided = false;
};

struct TriangleMesh {
  std::vector<Vec3> positions;   // world space
  std::vector<Vec3> normals;     // optional shading normals (world space, per vertex)
  std::vector<Vec2> uvs;         // optional
  std::vector<uint32_t> indices; // 3 per triangle
  int material = 0;
  std::optional<AreaEmission> emission;
  // pbrt: flip the geometric normal (ReverseOrientation xor a handedness-swapping transform).
  // Only used without shading normals; always go through triangle_normal().
  bool flip_normal = false;
  std::string source;            // where it came from, for `restir info` and error messages
  int animation = -1;            // index into Scene::animations (-1: static)
  size_t triangle_count() const { return indices.size() / 3; }
};

struct Sphere {
  Vec3 center;
  float radius = 1;
  int material = 0;
  std::optional<AreaEmission> emission;
  bool flip_normal = false;      // ReverseOrientation: normals (and emission) point inward
  int animation = -1;
};

struct PointLight {
  Vec3 position;
  Rgb intensity{1};              // I (W/sr), scale applied
  int animation = -1;
};

// pbrt-v4 "spot": a point light whose intensity toward a unit direction w (from the light) is
// I * smoothstep(cos_falloff_end, cos_falloff_start, dot(direction, w)) (pbrt-v4 SpotLight::I).
struct SpotLight {
  Vec3 position;
  Vec3 direction{0, 0, 1};       // unit cone axis, world space (normalize(to - from) under the CTM)
  Rgb intensity{1};              // I (W/sr) on the axis, scale applied
  float cone_angle = 30;         // degrees: total width (pbrt-v4 "coneangle"); kept for the exporter
  float cone_delta = 5;          // degrees: width of the falloff band ("conedeltaangle")
  float cos_falloff_start() const { return std::cos((cone_angle - cone_delta) * kPi / 180); }
  float cos_falloff_end() const { return std::cos(cone_angle * kPi / 180); }
  int animation = -1;            // moves position and axis rigidly, scales intensity
};

// pbrt-v4 "distant": radiance L arriving along one direction from infinitely far (delta direction).
struct DistantLight {
  Vec3 direction{0, 0, 1};       // unit, world space, TOWARD the light (normalize(from - to) under the CTM)
  Rgb radiance{1};               // L, scale (and illuminance) applied
  int animation = -1;            // turns the direction (its translation is ignored), scales radiance
};

// Infinite light: constant radiance, or an HDR image in equirectangular (2:1, as most HDRI sites
// ship) or pbrt-v4's equal-area octahedral (square) parameterization.
struct EnvironmentLight {
  enum class Mapping { constant, equirect, equal_area };
  Mapping mapping = Mapping::constant;
  Rgb radiance{1};               // constant colour, or the multiplier ("scale") for an image
  Image image;
  Mat4 world_from_light;         // orientation of the map
  Mat4 light_from_world;
  std::string filename;
  int animation = -1;            // rotation (its translation is ignored) and intensity
};

// A pinhole perspective camera (pbrt "perspective", no lens).
struct CameraKey {
  Mat4 camera_from_world;        // pbrt convention: left-handed camera space, +z forward
  float fov_degrees = 90;        // angle of the image's shorter axis (pbrt-v4 "fov")
};

struct Camera {
  std::vector<CameraKey> keys;   // one key = static; more = animated across the frames
  // Camera transform for frame f of n: linear interpolation of eye/target/up between keys
  // spread evenly over the frames (keys[0] at frame 0, keys.back() at frame n-1).
  CameraKey at_frame(int frame, int frame_count) const;
};

// What the scene file says about rendering; used as defaults that options may override.
struct SceneHints {
  std::optional<int> width, height, spp, max_depth;
  std::optional<std::string> pixel_filter;       // "box" | "triangle" | "gaussian"
  std::optional<float> filter_radius;
  // Where each hint was given ("file:line: Film \"integer xresolution\""), keyed by the option it
  // sets (film.width, ...), so that an out-of-range value is reported at its source.
  std::map<std::string, std::string> where;
};

// Unit geometric normal of triangle `tri` with pbrt-v4's orientation rule
// (Triangle::InteractionFromIntersection): with shading normals it is flipped to their side
// (judged at the centroid), otherwise by flip_normal. Zero-area triangles give a zero vector.
// Every consumer (intersection, emission, light sampling) must use this one function.
// The same over raw arrays (normals may be null), for device code (scene_view.h).
RESTIR_HD inline Vec3 triangle_normal(const Vec3* positions, const Vec3* normals, const uint32_t* indices, bool flip_normal,
                                      uint32_t tri) {
  const uint32_t i0 = indices[3 * tri], i1 = indices[3 * tri + 1], i2 = indices[3 * tri + 2];
  Vec3 n = cross(positions[i1] - positions[i0], positions[i2] - positions[i0]);
  float len = length(n);
  if (!(len > 0)) return Vec3(0);
  n = n / len;
  if (normals) return face_forward(n, normals[i0] + normals[i1] + normals[i2]);
  return flip_normal ? -n : n;
}
inline Vec3 triangle_normal(const TriangleMesh& m, uint32_t tri) {
  return triangle_normal(m.positions.data(), m.normals.empty() ? nullptr : m.normals.data(), m.indices.data(), m.flip_normal, tri);
}

struct Scene {
  std::vector<TriangleMesh> meshes;
  std::vector<Sphere> spheres;
  std::vector<Material> materials;   // index 0 always exists (default diffuse 0.5)
  std::vector<Texture> textures;
  std::vector<PointLight> point_lights;
  std::vector<SpotLight> spot_lights;
  std::vector<DistantLight> distant_lights;
  std::optional<EnvironmentLight> environment;
  // Keyframed motion of the shapes and lights whose `animation` indexes it (animation.h); the
  // geometry above is the rest pose, animate_scene() gives frame f.
  std::vector<Animation> animations;
  Camera camera;
  SceneHints hints;
  std::string source_path;
  // Every file the scene was read from (the scene, included files, meshes, images), for refusing
  // to write an output onto an input and for content hashes.
  std::vector<std::string> input_files;

  Bounds3 bounds() const;
  size_t triangle_count() const;
};

}  // namespace rl
