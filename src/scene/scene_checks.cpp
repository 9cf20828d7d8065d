#include "scene/scene_checks.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "scene/loader.h"

namespace rl {
namespace {

bool finite(Vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
bool in_world(Vec3 v) {
  return finite(v) && std::fabs(v.x) <= kMaxWorldCoordinate && std::fabs(v.y) <= kMaxWorldCoordinate &&
         std::fabs(v.z) <= kMaxWorldCoordinate;
}
bool non_negative(Rgb c) { return finite(c) && c.x >= 0 && c.y >= 0 && c.z >= 0; }
std::string str(Vec3 v) { return fmt::format("({}, {}, {})", v.x, v.y, v.z); }

// A mesh's source is "file:line" (pbrt) or "file:shape" (OBJ, glTF): SceneError with line 0
// prints it as given.
[[noreturn]] void fail(const std::string& where, const std::string& msg) { throw SceneError(where, 0, msg); }

void check_point(const std::string& where, const char* what, Vec3 p) {
  if (!finite(p)) fail(where, fmt::format("{} {} is not finite", what, str(p)));
  if (!in_world(p))
    fail(where, fmt::format("{} {} lies beyond the supported world extent (|coordinate| <= {:g})", what, str(p),
                            kMaxWorldCoordinate));
}

void check_meshes(const Scene& s) {
  for (const TriangleMesh& m : s.meshes) {
    std::string where = m.source.empty() ? s.source_path : m.source;
    if (where.ends_with(':')) where.pop_back();  // OBJ/glTF "file:name" with an unnamed shape
    if (m.indices.empty()) fail(where, "mesh has no triangles");
    for (size_t i = 0; i < m.positions.size(); ++i)
      check_point(where, fmt::format("vertex {}", i).c_str(), m.positions[i]);
    for (size_t i = 0; i < m.normals.size(); ++i)
      if (!finite(m.normals[i])) fail(where, fmt::format("normal {} {} is not finite", i, str(m.normals[i])));
    for (size_t i = 0; i < m.uvs.size(); ++i)
      if (!std::isfinite(m.uvs[i].x) || !std::isfinite(m.uvs[i].y)) fail(where, fmt::format("uv {} is not finite", i));
    if (m.emission && !non_negative(m.emission->radiance))
      fail(where, fmt::format("emitted radiance {} must be finite and >= 0", str(m.emission->radiance)));
  }
  for (size_t i = 0; i < s.spheres.size(); ++i) {
    const Sphere& sp = s.spheres[i];
    std::string where = fmt::format("{}: sphere {}", s.source_path, i);
    check_point(where, "centre", sp.center);
    if (!(sp.radius > 0 && sp.radius <= kMaxWorldCoordinate))
      fail(where, fmt::format("radius {} must be in (0, {:g}] after the transform", sp.radius, kMaxWorldCoordinate));
    if (sp.emission && !non_negative(sp.emission->radiance))
      fail(where, fmt::format("emitted radiance {} must be finite and >= 0", str(sp.emission->radiance)));
  }
}

void check_materials(const Scene& s) {
  for (const Material& m : s.materials) {
    std::string where = fmt::format("{}: material '{}'", s.source_path, m.name);
    auto in01 = [](Rgb c) { return non_negative(c) && c.x <= 1 && c.y <= 1 && c.z <= 1; };
    if (!in01(m.reflectance)) fail(where, fmt::format("reflectance {} must be in [0, 1]", str(m.reflectance)));
    if (!non_negative(m.eta) || !(std::min(m.eta.x, std::min(m.eta.y, m.eta.z)) > 0)) fail(where, fmt::format("eta {} must be > 0", str(m.eta)));
    if (!non_negative(m.k)) fail(where, fmt::format("k {} must be finite and >= 0", str(m.k)));
    if (!(std::isfinite(m.ior) && m.ior > 0)) fail(where, fmt::format("eta {} must be > 0", m.ior));
    if (!(std::isfinite(m.alpha_x) && m.alpha_x >= 0 && std::isfinite(m.alpha_y) && m.alpha_y >= 0))
      fail(where, fmt::format("roughness ({}, {}) must be finite and >= 0", m.alpha_x, m.alpha_y));
  }
  for (const Texture& t : s.textures) {
    std::string where = fmt::format("{}: texture '{}'", s.source_path, t.name);
    for (float v : {t.uscale, t.vscale, t.udelta, t.vdelta})
      if (!std::isfinite(v)) fail(where, "uv mapping (uscale, vscale, udelta, vdelta) must be finite");
    if (!finite(t.value) || !finite(t.tex1) || !finite(t.tex2)) fail(where, "texture values must be finite");
    for (const Rgb& c : t.image.pixels)
      if (!finite(c)) fail(where, "the image has non-finite pixels (NaN or infinity)");
  }
}

void check_lights_and_camera(const Scene& s) {
  for (size_t i = 0; i < s.point_lights.size(); ++i) {
    std::string where = fmt::format("{}: point light {}", s.source_path, i);
    check_point(where, "position", s.point_lights[i].position);
    if (!non_negative(s.point_lights[i].intensity)) fail(where, "intensity must be finite and >= 0");
  }
  for (size_t i = 0; i < s.spot_lights.size(); ++i) {
    const SpotLight& l = s.spot_lights[i];
    std::string where = fmt::format("{}: spot light {}", s.source_path, i);
    check_point(where, "position", l.position);
    if (!non_negative(l.intensity)) fail(where, "intensity must be finite and >= 0");
    if (!(std::fabs(length(l.direction) - 1) < 1e-3f)) fail(where, fmt::format("direction {} is not a unit vector", str(l.direction)));
    if (!(l.cone_angle > 0 && l.cone_angle <= 180 && l.cone_delta >= 0 && l.cone_delta <= l.cone_angle))
      fail(where, fmt::format("cone angle {} and falloff band {} must satisfy 0 <= band <= angle, 0 < angle <= 180", l.cone_angle,
                              l.cone_delta));
  }
  for (size_t i = 0; i < s.distant_lights.size(); ++i) {
    const DistantLight& l = s.distant_lights[i];
    std::string where = fmt::format("{}: distant light {}", s.source_path, i);
    if (!non_negative(l.radiance)) fail(where, "radiance must be finite and >= 0");
    if (!(std::fabs(length(l.direction) - 1) < 1e-3f)) fail(where, fmt::format("direction {} is not a unit vector", str(l.direction)));
  }
  if (const auto& e = s.environment) {
    std::string where = e->filename.empty() ? s.source_path : e->filename;
    if (!non_negative(e->radiance)) fail(where, "environment radiance must be finite and >= 0");
    for (const Rgb& c : e->image.pixels)
      if (!finite(c)) fail(where, "the environment image has non-finite pixels (NaN or infinity)");
  }
  for (size_t k = 0; k < s.camera.keys.size(); ++k) {
    const CameraKey& key = s.camera.keys[k];
    std::string where = fmt::format("{}: camera", s.source_path);
    Mat4 inv;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c)
        if (!std::isfinite(key.camera_from_world.m[r][c])) fail(where, "camera transform is not finite");
    if (!key.camera_from_world.inverse(inv)) fail(where, "camera transform is singular");
    check_point(where, "position", inv.apply_point(Vec3(0)));
    if (!(key.fov_degrees > 0 && key.fov_degrees < 180)) fail(where, fmt::format("fov {} must be in (0, 180)", key.fov_degrees));
  }
}

}  // namespace

void validate_scene(const Scene& scene) {
  check_meshes(scene);
  check_materials(scene);
  check_lights_and_camera(scene);
}

bool scene_has_lights(const Scene& s) {
  if (s.environment) return true;
  for (const PointLight& l : s.point_lights)
    if (max_component(l.intensity) > 0) return true;
  for (const SpotLight& l : s.spot_lights)
    if (max_component(l.intensity) > 0) return true;
  for (const DistantLight& l : s.distant_lights)
    if (max_component(l.radiance) > 0) return true;
  for (const TriangleMesh& m : s.meshes)
    if (m.emission && max_component(m.emission->radiance) > 0) return true;
  for (const Sphere& sp : s.spheres)
    if (sp.emission && max_component(sp.emission->radiance) > 0) return true;
  return false;
}

void warn_if_no_lights(const Scene& scene) {
  if (!scene_has_lights(scene))
    std::fprintf(stderr, "%s: warning: the scene has no light source (no emitting shape, point, spot, distant or environment light): "
                 "the image will be black\n", scene.source_path.c_str());
}

}  // namespace rl
