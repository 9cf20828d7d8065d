#include "scene/loader.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>

#include "image/image_io.h"
#include "scene/ply.h"
#include "scene/scene_checks.h"

namespace rl {

static std::string format_error(const std::string& file, int line, const std::string& message) {
  std::string s;
  s.append(file);
  if (line > 0) {
    s.push_back(':');
    s.append(std::to_string(line));
  }
  s.append(": ");
  s.append(message);
  // One line, always.
  std::replace(s.begin(), s.end(), '\n', ' ');
  std::replace(s.begin(), s.end(), '\r', ' ');
  return s;
}

SceneError::SceneError(const std::string& file, int line, const std::string& message)
    : std::runtime_error(format_error(file, line, message)), file_(file), line_(line), message_(message) {}

SceneError::SceneError(const std::string& message)
    : std::runtime_error(message), line_(0), message_(message), located_(false) {}

CameraKey default_camera(const Bounds3& bounds) {
  CameraKey key;
  key.fov_degrees = 45;
  Vec3 c(0), eye(0, 0, 1);
  float r = 1;
  if (!bounds.empty()) {
    c = bounds.center();
    r = 0.5f * length(bounds.diagonal());
    if (!(r > 0)) r = 1;
  }
  eye = c + Vec3(0, 0, 1.5f * r);
  Mat4 cfw;
  look_at(eye, c, Vec3(0, 1, 0), cfw);  // cannot fail: eye != c, up not parallel to -z
  key.camera_from_world = scale(Vec3(-1, 1, 1)) * cfw;
  return key;
}

namespace detail {

bool located(const std::exception& e) {
  const auto* s = dynamic_cast<const SceneError*>(&e);
  return s && s->located();
}

TriangleMesh make_world_mesh(const std::vector<Vec3>& p, const std::vector<Vec3>& n, const std::vector<Vec2>& uv,
                             const std::vector<uint32_t>& indices, const Mat4& xf, bool reverse_orientation) {
  if (indices.size() % 3 != 0) throw SceneError("number of indices is not a multiple of 3");
  if (!n.empty() && n.size() != p.size())
    throw SceneError("\"N\" has " + std::to_string(n.size()) + " entries but \"P\" has " + std::to_string(p.size()));
  if (!uv.empty() && uv.size() != p.size())
    throw SceneError("\"uv\" has " + std::to_string(uv.size()) + " entries but \"P\" has " + std::to_string(p.size()));
  for (uint32_t i : indices)
    if (i >= p.size())
      throw SceneError("vertex index " + std::to_string(i) + " out of range (" + std::to_string(p.size()) +
                       " vertices)");
  Mat4 inv;
  if (!xf.inverse(inv)) throw SceneError("singular transform");
  TriangleMesh m;
  m.positions.reserve(p.size());
  for (const Vec3& q : p) m.positions.push_back(xf.apply_point(q));
  for (const Vec3& q : n) {
    Vec3 w = Mat4::apply_normal_with_inverse(inv, q);
    float len = length(w);
    w = len > 0 ? w / len : Vec3(0);
    m.normals.push_back(reverse_orientation ? -w : w);  // pbrt-v4 TriangleMesh negates N
  }
  m.uvs = uv;
  m.indices = indices;
  bool flip = reverse_orientation != (xf.det3() < 0);
  m.flip_normal = flip;
  if (!m.normals.empty()) {
    for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {
      uint32_t i0 = m.indices[t], i1 = m.indices[t + 1], i2 = m.indices[t + 2];
      Vec3 ng = cross(m.positions[i1] - m.positions[i0], m.positions[i2] - m.positions[i0]);
      if (flip) ng = -ng;
      Vec3 ns = m.normals[i0] + m.normals[i1] + m.normals[i2];  // interpolated N at the centroid
      // pbrt: n = FaceForward(n, ns). Disagreement -> swap winding so the resolved normal flips.
      if (dot(ng, ns) < 0) std::swap(m.indices[t + 1], m.indices[t + 2]);
    }
  }
  return m;
}

void transform_mesh(TriangleMesh& m, const Mat4& xf) {
  Mat4 inv;
  if (!xf.inverse(inv)) throw SceneError("singular transform");
  for (Vec3& q : m.positions) q = xf.apply_point(q);
  for (Vec3& q : m.normals) {
    Vec3 w = Mat4::apply_normal_with_inverse(inv, q);
    float len = length(w);
    q = len > 0 ? w / len : Vec3(0);
  }
  // Positions transformed by a mirroring xf flip cross(p1-p0, p2-p0) relative to the properly
  // transformed normal; compensate so the resolved normal is the transformed one.
  if (xf.det3() < 0) m.flip_normal = !m.flip_normal;
}

Image read_image_for(const std::string& image_path, const std::string& file, int line) {
  {
    std::ifstream f(image_path, std::ios::binary);
    if (!f) throw SceneError(file, line, "cannot open image file '" + image_path + "'");
  }
  try {
    Image img = read_image(image_path);
    if (img.empty()) throw SceneError("empty image");
    return img;
  } catch (const std::exception& e) {
    if (located(e)) throw;
    throw SceneError(file, line, "cannot read image '" + image_path + "': " + e.what());
  }
}

}  // namespace detail

static std::string lower_extension(const std::string& path) {
  size_t slash = path.find_last_of("/\\");
  size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string e = path.substr(dot + 1);
  for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

static void finish_mesh_scene(Scene& s) {
  if (s.meshes.empty()) throw SceneError(s.source_path, 0, "the file contains no triangles");
  if (s.camera.keys.empty()) s.camera.keys.push_back(default_camera(s.bounds()));
}

Scene load_pbrt(const std::string& path) {
  Scene s = detail::parse_pbrt(path);
  validate_scene(s);
  warn_if_no_lights(s);
  return s;
}

Scene load_scene(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw SceneError(path, 0, "is a directory, not a scene file");
  std::string ext = lower_extension(path);
  if (ext == "pbrt") return load_pbrt(path);
  {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw SceneError(path, 0, "cannot open scene file");
  }
  Scene s;
  s.source_path = path;
  s.input_files.push_back(path);
  s.materials.push_back(Material{});
  s.materials[0].name = "default";
  detail::MeshImport opt;
  opt.error_file = path;
  if (ext == "obj") {
    detail::import_obj(path, opt, s, s.meshes);
  } else if (ext == "gltf" || ext == "glb") {
    std::optional<CameraKey> cam;
    detail::import_gltf(path, opt, s, s.meshes, &cam);
    if (cam) s.camera.keys.push_back(*cam);
  } else if (ext == "ply") {
    PlyMesh pm = read_ply(path);
    try {
      TriangleMesh m = detail::make_world_mesh(pm.positions, pm.normals, pm.uvs, pm.indices, Mat4::identity(), false);
      m.source = path;
      s.meshes.push_back(std::move(m));
    } catch (const SceneError& e) {  // unlocated: the mesh's indices or arrays
      throw SceneError(path, 0, e.message());
    }
  } else {
    throw SceneError(path, 0, "unknown scene file extension '." + ext + "' (expected .pbrt, .obj, .gltf, .glb or .ply)");
  }
  finish_mesh_scene(s);
  validate_scene(s);
  warn_if_no_lights(s);
  return s;
}

}  // namespace rl
