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
  RESTIR_HD Ray generate_ray(Vec2 raster) const {
    // Raster -> screen -> camera -> world is linear in the raster position up to the final
    // normalization (pbrt's raster-from-screen, then the linear part of world_from_camera), so the constructor
    // folds it into origin_dir_ + x * dir_dx_ + y * dir_dy_: one normalization and no division
    // per ray (the camera ray was ~12% of the path tracer's samples, issue 9).
    Ray r;
    r.o = position_;
    r.d = normalize(origin_dir_ + dir_dx_ * raster.x + dir_dy_ * raster.y);
    return r;
  }
  // Raster position of a world point; false when it is behind the camera or off the film.
  RESTIR_HD bool project(Vec3 world, Vec2& raster) const {
    const Vec3 c = camera_from_world_.apply_point(world);
    if (c.z <= 0) return false;
    const float sx = c.x / (c.z * tan_half_), sy = c.y / (c.z * tan_half_);
    raster = {(sx / sx_ + 1) * 0.5f * float(width_), (1 - sy / sy_) * 0.5f * float(height_)};
    return raster.x >= 0 && raster.y >= 0 && raster.x < float(width_) && raster.y < float(height_);
  }
  RESTIR_HD Vec3 position() const { return position_; }
  RESTIR_HD Vec3 forward() const { return forward_; }
  RESTIR_HD int width() const { return width_; }
  RESTIR_HD int height() const { return height_; }

 private:
  Mat4 world_from_camera_, camera_from_world_;
  Vec3 position_, forward_;
  Vec3 origin_dir_, dir_dx_, dir_dy_;  // world direction (unnormalized) of raster (0,0) and per pixel in x, y
  float tan_half_ = 1;    // tan(fov / 2)
  float sx_ = 1, sy_ = 1;  // screen half extents: the window [-sx, sx] x [-sy, sy] (pbrt's screen window)
  int width_, height_;
};

// Reads {"keys": [{"eye": [..], "target": [..], "up": [..], "fov": deg}, ...]} into camera.keys;
// a key's optional "mirror": true mirrors its image left-right (pbrt's Scale -1 1 1).
// Throws SceneError naming the file on any problem.
void load_camera_path(const std::string& path, Camera& camera);

}  // namespace rl
