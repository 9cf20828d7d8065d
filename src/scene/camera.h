// Pinhole perspective camera for one frame (pbrt-v4 PerspectiveCamera without lens), and the
// keyframed camera path loaded from JSON.
#pragma once
#include <string>

#include "core/math.h"
#include "scene/scene.h"

namespace rl {

class PerspectiveCamera {
 public:
  PerspectiveCamera(const CameraKey& key, int width, int height);
  // Primary ray through the raster position (x right, y down, in pixels; (0,0) is the top-left corner).
  Ray generate_ray(Vec2 raster) const;
  // Raster position of a world point; false when it is behind the camera or off the film.
  bool project(Vec3 world, Vec2& raster) const;
  Vec3 position() const { return position_; }
  Vec3 forward() const { return forward_; }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  Mat4 world_from_camera_, camera_from_world_;
  Vec3 position_, forward_;
  float tan_half_ = 1, aspect_ = 1;  // screen window [-aspect, aspect] x [-1, 1] (or swapped)
  float sx_ = 1, sy_ = 1;            // screen half extents
  int width_, height_;
};

// Reads {"keys": [{"eye": [..], "target": [..], "up": [..], "fov": deg}, ...]} into camera.keys;
// a key's optional "mirror": true mirrors its image left-right (pbrt's Scale -1 1 1).
// Throws std::runtime_error naming the file on any problem.
void load_camera_path(const std::string& path, Camera& camera);

}  // namespace rl
