#include "core/math.h"

namespace rl {

bool Mat4::inverse(Mat4& out) const {
  // Gauss-Jordan elimination with partial pivoting, in double for stability.
  double a[4][8];
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      a[i][j] = m[i][j];
      a[i][j + 4] = i == j ? 1.0 : 0.0;
    }
  for (int c = 0; c < 4; ++c) {
    int piv = c;
    for (int r = c + 1; r < 4; ++r)
      if (std::fabs(a[r][c]) > std::fabs(a[piv][c])) piv = r;
    if (std::fabs(a[piv][c]) < 1e-12) return false;
    if (piv != c)
      for (int j = 0; j < 8; ++j) std::swap(a[c][j], a[piv][j]);
    double inv = 1.0 / a[c][c];
    for (int j = 0; j < 8; ++j) a[c][j] *= inv;
    for (int r = 0; r < 4; ++r) {
      if (r == c) continue;
      double f = a[r][c];
      for (int j = 0; j < 8; ++j) a[r][j] -= f * a[c][j];
    }
  }
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) out.m[i][j] = float(a[i][j + 4]);
  return true;
}

Mat4 translate(Vec3 d) {
  Mat4 r;
  for (int i = 0; i < 3; ++i) r.m[i][3] = d[i];
  return r;
}

Mat4 scale(Vec3 s) {
  Mat4 r;
  for (int i = 0; i < 3; ++i) r.m[i][i] = s[i];
  return r;
}

Mat4 rotate(float degrees, Vec3 axis) {
  // Rodrigues' rotation about a normalized axis (pbrt-v4 Rotate()).
  Vec3 a = normalize(axis);
  float th = degrees * kPi / 180.0f;
  float s = std::sin(th), c = std::cos(th);
  Mat4 r;
  r.m[0][0] = a.x * a.x + (1 - a.x * a.x) * c;
  r.m[0][1] = a.x * a.y * (1 - c) - a.z * s;
  r.m[0][2] = a.x * a.z * (1 - c) + a.y * s;
  r.m[1][0] = a.x * a.y * (1 - c) + a.z * s;
  r.m[1][1] = a.y * a.y + (1 - a.y * a.y) * c;
  r.m[1][2] = a.y * a.z * (1 - c) - a.x * s;
  r.m[2][0] = a.x * a.z * (1 - c) - a.y * s;
  r.m[2][1] = a.y * a.z * (1 - c) + a.x * s;
  r.m[2][2] = a.z * a.z + (1 - a.z * a.z) * c;
  return r;
}

bool look_at(Vec3 eye, Vec3 target, Vec3 up, Mat4& camera_from_world) {
  Vec3 dir = target - eye;
  if (length(dir) == 0) return false;
  dir = normalize(dir);
  if (length(up) == 0) return false;
  Vec3 right = cross(normalize(up), dir);
  if (length(right) < 1e-8f) return false;  // up parallel to view direction
  right = normalize(right);
  Vec3 new_up = cross(dir, right);
  Mat4 world_from_camera;
  for (int i = 0; i < 3; ++i) {
    world_from_camera.m[i][0] = right[i];
    world_from_camera.m[i][1] = new_up[i];
    world_from_camera.m[i][2] = dir[i];
    world_from_camera.m[i][3] = eye[i];
  }
  return world_from_camera.inverse(camera_from_world);
}

}  // namespace rl
