#include "viewer/camera_controller.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace rl::viewer {

namespace {

// Rotation of v about the unit axis a (Rodrigues).
Vec3 rotate_about(Vec3 v, Vec3 a, float degrees) {
  const float t = degrees * kPi / 180.0f, c = std::cos(t), s = std::sin(t);
  return v * c + cross(a, v) * s + a * (dot(a, v) * (1 - c));
}

}  // namespace

CameraController::CameraController(const CameraKey& home, const Bounds3& scene_bounds) : home_(home) {
  const float size = scene_bounds.empty() ? 1.0f : length(scene_bounds.diagonal());
  size_ = size > 0 && std::isfinite(size) ? size : 1.0f;
  Mat4 world_from_camera;
  if (!home.camera_from_world.inverse(world_from_camera)) world_from_camera = Mat4{};
  home_eye_ = world_from_camera.apply_point(Vec3(0));
  const Vec3 forward = normalize(world_from_camera.apply_vector(Vec3(0, 0, 1)));
  home_up_ = normalize(world_from_camera.apply_vector(Vec3(0, 1, 0)));
  // Orbit about the point of the view axis nearest the scene's centre (half the scene's size
  // ahead when the centre is behind the camera).
  float ahead = scene_bounds.empty() ? 0.0f : dot(scene_bounds.center() - home_eye_, forward);
  home_target_ = home_eye_ + forward * (ahead > 1e-3f * size_ ? ahead : 0.5f * size_);
  mirrored_ = home.camera_from_world.det3() < 0;
  fov_ = home.fov_degrees;
  reset();
}

void CameraController::reset() {
  eye_ = home_eye_;
  target_ = home_target_;
  up_ = home_up_;
  ++version_;
}

Vec3 CameraController::right_axis() const {
  // The screen's right in world space: the camera's +x, which a mirrored camera flips.
  Vec3 r = normalize(cross(up_, normalize(target_ - eye_)));
  return mirrored_ ? -r : r;
}

void CameraController::rotate(float yaw, float pitch) {
  const Vec3 axis = normalize(up_);
  const bool orbit = mode_ == CameraMode::orbit;
  // A mirrored camera shows the world flipped left-right: turn the other way so that a drag to the
  // right looks the same on screen.
  if (mirrored_) yaw = -yaw;
  // Orbit: the eye turns around the target; fly: the target turns around the eye.
  Vec3 arm = orbit ? eye_ - target_ : target_ - eye_;
  arm = rotate_about(arm, axis, orbit ? -yaw : yaw);
  const Vec3 side = normalize(cross(axis, normalize(arm)));
  const Vec3 turned = rotate_about(arm, side, orbit ? pitch : -pitch);
  // Keep 2 degrees off the poles, where the up vector would be parallel to the view.
  if (std::fabs(dot(normalize(turned), axis)) < std::cos(2.0f * kPi / 180.0f)) arm = turned;
  if (orbit) eye_ = target_ + arm;
  else target_ = eye_ + arm;
  ++version_;
}

void CameraController::move(Vec3 local) {
  const Vec3 forward = normalize(target_ - eye_);
  const Vec3 right = right_axis();
  const Vec3 up = normalize(cross(forward, normalize(cross(up_, forward))));
  const Vec3 pan = (right * local.x + up * local.y) * size_;
  const float along = local.z * size_;
  if (mode_ == CameraMode::orbit) {
    // Dolly toward the target, stopping short of it (a zero-length view direction has no camera).
    const float dist = length(target_ - eye_);
    eye_ = eye_ + forward * std::min(along, dist - 1e-3f * size_);
    eye_ = eye_ + pan;
    target_ = target_ + pan;
  } else {
    const Vec3 d = pan + forward * along;
    eye_ = eye_ + d;
    target_ = target_ + d;
  }
  ++version_;
}

CameraKey CameraController::key() const {
  CameraKey k;
  k.fov_degrees = fov_;
  Mat4 m;
  if (!look_at(eye_, target_, up_, m)) return home_;
  k.camera_from_world = mirrored_ ? scale(Vec3(-1, 1, 1)) * m : m;
  return k;
}

std::string camera_path_json(const std::vector<PathKey>& keys) {
  auto vec = [](Vec3 v) { return fmt::format("[{:.9g}, {:.9g}, {:.9g}]", v.x, v.y, v.z); };
  std::string s = "{\"keys\": [\n";
  for (size_t i = 0; i < keys.size(); ++i) {
    const PathKey& k = keys[i];
    s += fmt::format("  {{\"eye\": {}, \"target\": {}, \"up\": {}, \"fov\": {:.9g}{}}}{}\n", vec(k.eye), vec(k.target),
                     vec(k.up), k.fov, k.mirror ? ", \"mirror\": true" : "", i + 1 < keys.size() ? "," : "");
  }
  return s + "]}\n";
}

}  // namespace rl::viewer
