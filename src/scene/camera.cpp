#include "scene/camera.h"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "scene/loader.h"

namespace rl {

CameraKey Camera::at_frame(int frame, int frame_count) const {
  if (keys.empty()) return {};
  if (keys.size() == 1 || frame_count <= 1) return keys.front();
  // Keys are spread evenly over the frames; interpolate the camera-to-world frame linearly and
  // re-orthonormalize, keeping the handedness of the keys (pbrt scenes often mirror with Scale -1 1 1).
  float t = float(frame) / float(frame_count - 1) * float(keys.size() - 1);
  size_t k = std::min(size_t(t), keys.size() - 2);
  float f = t - float(k);
  Mat4 a, b;
  if (!keys[k].camera_from_world.inverse(a) || !keys[k + 1].camera_from_world.inverse(b)) return keys[k];
  Vec3 col[4];
  for (int c = 0; c < 4; ++c)
    col[c] = lerp(f, Vec3{a.m[0][c], a.m[1][c], a.m[2][c]}, Vec3{b.m[0][c], b.m[1][c], b.m[2][c]});
  float handed = a.det3() < 0 ? -1.0f : 1.0f;
  Vec3 z = normalize(col[2]);
  Vec3 y = normalize(col[1] - z * dot(col[1], z));
  Vec3 x = cross(y, z) * handed;
  Mat4 w;
  for (int i = 0; i < 3; ++i) {
    w.m[i][0] = x[i];
    w.m[i][1] = y[i];
    w.m[i][2] = z[i];
    w.m[i][3] = col[3][i];
  }
  CameraKey out;
  w.inverse(out.camera_from_world);
  out.fov_degrees = lerp(f, keys[k].fov_degrees, keys[k + 1].fov_degrees);
  return out;
}

PerspectiveCamera::PerspectiveCamera(const CameraKey& key, int width, int height)
    : camera_from_world_(key.camera_from_world), width_(width), height_(height) {
  if (!camera_from_world_.inverse(world_from_camera_)) throw SceneError("camera transform is singular");
  position_ = world_from_camera_.apply_point(Vec3(0));
  forward_ = normalize(world_from_camera_.apply_vector(Vec3(0, 0, 1)));
  // pbrt-v4: the fov spans the shorter image axis; the screen window is [-ratio, ratio] on the longer one.
  tan_half_ = std::tan(key.fov_degrees * 0.5f * kPi / 180.0f);
  float ratio = float(width) / float(height);
  if (ratio > 1) {
    sx_ = ratio;
    sy_ = 1;
  } else {
    sx_ = 1;
    sy_ = 1 / ratio;
  }
  // Screen x = (raster.x / width * 2 - 1) sx, y = (1 - raster.y / height * 2) sy; camera-space
  // direction (x tan, y tan, 1); world direction = its columns of world_from_camera (see generate_ray).
  const Vec3 c0 = world_from_camera_.apply_vector(Vec3(1, 0, 0)), c1 = world_from_camera_.apply_vector(Vec3(0, 1, 0)),
             c2 = world_from_camera_.apply_vector(Vec3(0, 0, 1));
  dir_dx_ = c0 * (2 * sx_ * tan_half_ / float(width));
  dir_dy_ = c1 * (-2 * sy_ * tan_half_ / float(height));
  origin_dir_ = c0 * (-sx_ * tan_half_) + c1 * (sy_ * tan_half_) + c2;
}

namespace {
// where: "key I" of the camera path `path`.
Vec3 json_vec3(const nlohmann::json& j, const char* key, const std::string& path, const std::string& where) {
  if (!j.contains(key) || !j[key].is_array() || j[key].size() != 3)
    throw SceneError(path, 0, fmt::format("{}: '{}' must be an array of 3 numbers", where, key));
  Vec3 v;
  for (int i = 0; i < 3; ++i) {
    if (!j[key][size_t(i)].is_number()) throw SceneError(path, 0, fmt::format("{}: '{}' must hold numbers", where, key));
    double d = j[key][size_t(i)].get<double>();
    // Beyond the world extent a camera puts rays where Embree cannot trace them.
    if (!(std::fabs(d) <= kMaxWorldCoordinate))
      throw SceneError(path, 0, fmt::format("{}: '{}' value {} is out of range [-{:g}, {:g}]", where, key, d,
                                            kMaxWorldCoordinate, kMaxWorldCoordinate));
    v[i] = float(d);
  }
  return v;
}
}  // namespace

void load_camera_path(const std::string& path, Camera& camera) {
  std::ifstream in(path);
  if (!in) throw SceneError(path, 0, "cannot open camera path");
  std::stringstream ss;
  ss << in.rdbuf();
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(ss.str());
  } catch (const nlohmann::json::exception& e) {  // parse_error, and out_of_range for 1e400
    throw SceneError(path, 0, std::string("invalid JSON: ") + e.what());
  }
  if (!j.is_object() || !j.contains("keys") || !j["keys"].is_array() || j["keys"].empty())
    throw SceneError(path, 0, "expected {\"keys\": [ ... ]} with at least one key");
  std::vector<CameraKey> keys;
  for (size_t i = 0; i < j["keys"].size(); ++i) {
    const auto& k = j["keys"][i];
    const std::string where = fmt::format("key {}", i);
    if (!k.is_object()) throw SceneError(path, 0, where + ": expected an object");
    CameraKey key;
    Vec3 up = k.contains("up") ? json_vec3(k, "up", path, where) : Vec3(0, 1, 0);
    if (!look_at(json_vec3(k, "eye", path, where), json_vec3(k, "target", path, where), up, key.camera_from_world))
      throw SceneError(path, 0, where + ": eye, target and up do not define a camera");
    // "mirror": true flips the image left-right, as pbrt scenes do with Scale -1 1 1 before
    // LookAt; the viewer writes it when it records such a scene's camera.
    if (k.contains("mirror")) {
      if (!k["mirror"].is_boolean()) throw SceneError(path, 0, where + ": 'mirror' must be true or false");
      if (k["mirror"].get<bool>()) key.camera_from_world = scale(Vec3(-1, 1, 1)) * key.camera_from_world;
    }
    if (k.contains("fov")) {
      if (!k["fov"].is_number()) throw SceneError(path, 0, where + ": 'fov' must be a number");
      double fov = k["fov"].get<double>();
      key.fov_degrees = std::isfinite(fov) && std::fabs(fov) < 1e6 ? float(fov) : -1.0f;
      if (!(key.fov_degrees > 0 && key.fov_degrees < 180)) throw SceneError(path, 0, where + ": 'fov' must be in (0, 180)");
    } else if (!camera.keys.empty()) {
      key.fov_degrees = camera.keys.front().fov_degrees;
    }
    keys.push_back(key);
  }
  camera.keys = std::move(keys);
}

}  // namespace rl
