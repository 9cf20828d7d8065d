// Interactive camera of the viewer: orbit around a target or fly (mouse look + WASD), starting
// from (and reset to) the scene's camera, and a recorder that writes the camera of each rendered
// frame in the format `render.camera_path` reads, so that a session becomes a study input.
#pragma once
#include <string>
#include <vector>

#include "core/math.h"
#include "scene/scene.h"

namespace rl::viewer {

enum class CameraMode { orbit, fly };

// One camera path key (the JSON format of render.camera_path).
struct PathKey {
  Vec3 eye, target, up;
  float fov = 90;
  bool mirror = false;
};


class CameraController {
 public:
  // `home` is the scene's camera; the scene's size (its bounds' diagonal) scales movement.
  CameraController(const CameraKey& home, const Bounds3& scene_bounds);

  void reset();
  // Orbit mode: turn the eye around the target (yaw about the home camera's up, pitch about the
  // screen's right axis, kept off the poles). Fly mode: turn the view direction around the eye.
  void rotate(float yaw_degrees, float pitch_degrees);
  // Moves by (right, up, forward) x scene_size, in the current view's axes. Orbit mode: the
  // forward part dollies toward the target (never through it), right/up pan eye and target.
  void move(Vec3 local);
  void set_mode(CameraMode m) { mode_ = m; }
  CameraMode mode() const { return mode_; }

  CameraKey key() const;  // camera-from-world with the home camera's handedness, and fov
  Vec3 eye() const { return eye_; }
  Vec3 target() const { return target_; }
  Vec3 up() const { return up_; }
  float fov() const { return fov_; }
  bool mirrored() const { return mirrored_; }
  PathKey path_key() const { return {eye_, target_, up_, fov_, mirrored_}; }
  // Increments on every change: the renderer restarts its accumulation when it differs.
  unsigned version() const { return version_; }

 private:
  Vec3 right_axis() const;
  CameraKey home_;
  float size_ = 1;
  CameraMode mode_ = CameraMode::orbit;
  Vec3 eye_, target_, up_, home_eye_, home_target_, home_up_;
  float fov_ = 90;
  bool mirrored_ = false;  // pbrt scenes often mirror the camera (Scale -1 1 1)
  unsigned version_ = 0;
};

// {"keys": [{"eye": [..], "target": [..], "up": [..], "fov": f, "mirror": true?}, ...]}
std::string camera_path_json(const std::vector<PathKey>& keys);

}  // namespace rl::viewer
