// Screen-space ray marching for the ssr integrator (issue 12): where a world-space ray, seen
// through the camera, first passes behind the surface a pixel shows. Two marches over the same
// screen segment and the same hit test, so that the fast one can be tested against the plain one:
//   - march_linear: the perspective-correct DDA of McGuire and Mara 2014 ("Efficient GPU
//     screen-space ray tracing", JCGT 3(4)): one probe per pixel along the segment, bisection to the
//     crossing;
//   - march_hiz: hierarchical-depth traversal (Uludag 2014, "Hi-Z screen-space cone-traced
//     reflections", GPU Pro 5): a pyramid of the nearest view depth per 2^l x 2^l cell lets the
//     ray skip every cell it passes in front of, and descend to single pixels only where it may be
//     behind something. Each step visits one cell, so max_steps bounds the work, not the distance.
// Both treat a surface as a slab of thickness `thickness` x its view depth behind what the pixel
// shows, and accept a hit only on the side of the surface the camera sees (its lit colour is that
// side's). RESTIR_HD over views (issue 48: ssr on every backend), so the CPU and the GPU march the
// same code; the pyramid's levels lie one after another in one array.
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "frame/gbuffer.h"
#include "frame/reuse_pixel.h"
#include "scene/camera.h"

namespace rl {

inline constexpr int kMaxHiZLevels = 32;

// Where each level of a Hi-Z pyramid over width x height pixels lies: level 0 one value per pixel,
// level l covering 2^l x 2^l pixels ((w + 1) / 2 per halving), up to a single cell.
struct HiZLayout {
  int levels = 0;
  int width[kMaxHiZLevels] = {}, height[kMaxHiZLevels] = {};
  size_t offset[kMaxHiZLevels] = {};
  size_t total = 0;  // values in all levels
};
HiZLayout hiz_layout(int width, int height);

// Nearest view depth (distance along the camera's forward axis) per cell; +inf where every primary
// ray of the cell escaped.
struct HiZView {
  const float* z = nullptr;
  HiZLayout layout;
  RESTIR_HD float at(int level, int x, int y) const {
    return z[layout.offset[level] + size_t(y) * size_t(layout.width[level]) + size_t(x)];
  }
};

namespace ssr_detail {

inline constexpr float kInf = std::numeric_limits<float>::infinity();

// The ray as a screen-space segment: raster positions and view depths of its ends. Under a
// perspective projection 1/z and p/z are linear in screen space (McGuire and Mara 2014, §2), so
// the view depth at screen fraction a is 1 / lerp(1/z0, 1/z1, a).
struct ScreenSegment {
  Vec2 s0, s1;
  float z0 = 0, z1 = 0;
  float pixels = 0;  // length along the major axis, in pixels
  Vec3 o, e;         // world positions of the ends
  RESTIR_HD Vec2 at(float a) const { return s0 + (s1 - s0) * a; }
  RESTIR_HD float z_at(float a) const { return 1.0f / ((1 - a) / z0 + a / z1); }
  RESTIR_HD Vec3 point_at(float a) const { return (o * ((1 - a) / z0) + e * (a / z1)) * z_at(a); }
};

// Clips the ray to the near plane and the scene's extent and projects it; false when it starts
// behind the near plane or spans no pixel.
RESTIR_HD inline bool make_segment(const PerspectiveCamera& camera, Vec3 o, Vec3 d, float max_distance, ScreenSegment& seg) {
  const Vec3 cam = camera.position(), fwd = camera.forward();
  seg.z0 = dot(o - cam, fwd);
  const float near = 1e-4f * std::max(1.0f, max_distance);
  if (!(seg.z0 > near)) return false;
  float t1 = max_distance;
  const float dz = dot(d, fwd);
  if (dz < 0) t1 = std::min(t1, (near - seg.z0) / dz);
  const Vec3 e = o + d * t1;
  seg.o = o;
  seg.e = e;
  seg.z1 = dot(e - cam, fwd);
  camera.project(o, seg.s0);  // raster positions, on the film or not (both ends are in front)
  camera.project(e, seg.s1);
  seg.pixels = std::max(std::fabs(seg.s1.x - seg.s0.x), std::fabs(seg.s1.y - seg.s0.y));
  return seg.pixels >= 1e-3f && std::isfinite(seg.pixels);
}

RESTIR_HD inline bool on_film(Vec2 s, int w, int h) { return s.x >= 0 && s.y >= 0 && s.x < float(w) && s.y < float(h); }

// The ray arrived on the side of the pixel's surface that the camera sees, whichever way the
// mesh's winding points the normal.
RESTIR_HD inline bool faces_ray(const GSurface& s, Vec3 d) {
  const Vec3 seen = dot(s.ng, s.wo) >= 0 ? s.ng : -s.ng;
  return dot(seen, d) < 0;
}

// Screen fraction at which the segment leaves the axis-aligned cell [x0, x1) x [y0, y1).
RESTIR_HD inline float exit_fraction(const ScreenSegment& seg, float x0, float x1, float y0, float y1) {
  const Vec2 ds = seg.s1 - seg.s0;
  float a = kInf;
  if (ds.x > 0) a = std::min(a, (x1 - seg.s0.x) / ds.x);
  if (ds.x < 0) a = std::min(a, (x0 - seg.s0.x) / ds.x);
  if (ds.y > 0) a = std::min(a, (y1 - seg.s0.y) / ds.y);
  if (ds.y < 0) a = std::min(a, (y0 - seg.s0.y) / ds.y);
  return a;
}

}  // namespace ssr_detail

// Level 0 of the pyramid at a pixel: the view depth of the surface it shows (+inf: none).
RESTIR_HD inline float hiz_depth(const GPacked& s, Vec3 camera_position, Vec3 camera_forward) {
  return s.valid() ? dot(s.p - camera_position, camera_forward) : ssr_detail::kInf;
}
// Cell (cx, cy) of level `level` >= 1: the nearest of the (up to) 2 x 2 cells of the level below.
RESTIR_HD inline float hiz_reduce(const HiZView& h, int level, int cx, int cy) {
  const int fw = h.layout.width[level - 1], fh = h.layout.height[level - 1];
  float z = ssr_detail::kInf;
  for (int dy = 0; dy < 2; ++dy)
    for (int dx = 0; dx < 2; ++dx) {
      const int x = 2 * cx + dx, y = 2 * cy + dy;
      if (x < fw && y < fh) z = std::min(z, h.at(level - 1, x, y));
    }
  return z;
}

// A pyramid in host memory (tests and tools; the frame builds its own with the same functions).
struct HiZPyramid {
  std::vector<float> z;
  HiZLayout layout;
  void build(const PerspectiveCamera& camera, const GBuffer& g);
  HiZView view() const { return {z.data(), layout}; }
};

struct MarchResult {
  bool hit = false;
  int x = 0, y = 0;  // the pixel the ray landed on
  int steps = 0;     // probes (linear) or cells visited (Hi-Z)
};

// The ray (o, d), at most max_distance long, through the G-buffer g of `camera` and the pyramid
// built from it: one probe per pixel along the segment, then bisection to the crossing.
RESTIR_HD inline MarchResult march_linear(const PerspectiveCamera& camera, const GBufferView& g, const HiZView& hiz, Vec3 o, Vec3 d,
                                          float max_distance, int max_steps, float thickness) {
  using namespace ssr_detail;
  MarchResult r;
  ScreenSegment seg;
  if (!make_segment(camera, o, d, max_distance, seg)) return r;
  const int steps = std::min(max_steps, int(std::ceil(seg.pixels)));
  // How far the point at fraction a is behind the visible surface of its pixel (< 0: in front;
  // NaN: off the film); the pixel in x, y.
  const auto probe = [&](float a, int& x, int& y) {
    const Vec2 s = seg.at(a);
    if (!on_film(s, g.width, g.height)) return std::numeric_limits<float>::quiet_NaN();
    x = int(s.x);
    y = int(s.y);
    const float zs = hiz.at(0, x, y);
    return zs == kInf ? -1.0f : seg.z_at(a) - zs;
  };
  const auto in_slab = [&](float behind, int x, int y) { return behind > 0 && behind <= thickness * hiz.at(0, x, y); };
  float a_prev = 0;
  for (int i = 1; i <= steps; ++i) {
    r.steps = i;
    const float a = float(i) / float(steps);
    int x, y;
    const float behind = probe(a, x, y);
    if (std::isnan(behind)) return r;  // left the film
    if (in_slab(behind, x, y)) {
      // Bisection between the last point in front and this one, for the pixel where it crosses.
      float lo = a_prev, hi = a;
      for (int k = 0; k < 6; ++k) {
        const float mid = 0.5f * (lo + hi);
        int mx, my;
        const float b = probe(mid, mx, my);
        if (!std::isnan(b) && in_slab(b, mx, my)) {
          hi = mid;
          x = mx;
          y = my;
        } else {
          lo = mid;
        }
      }
      if (!faces_ray(g.at(x, y), d)) return r;
      r.hit = true;
      r.x = x;
      r.y = y;
      return r;
    }
    if (behind <= 0) a_prev = a;
  }
  return r;
}

// The same ray through the pyramid: skip every cell the ray passes in front of, descend where it
// may pass behind something (file comment).
RESTIR_HD inline MarchResult march_hiz(const PerspectiveCamera& camera, const GBufferView& g, const HiZView& hiz, Vec3 o, Vec3 d,
                                       float max_distance, int max_steps, float thickness) {
  using namespace ssr_detail;
  MarchResult r;
  ScreenSegment seg;
  if (!make_segment(camera, o, d, max_distance, seg)) return r;
  const int top = hiz.layout.levels - 1;
  const float nudge = 1e-3f / seg.pixels;  // a thousandth of a pixel: past a cell's border
  const auto cell_exit = [&](float a, int level, int& cx, int& cy) {
    const Vec2 s = seg.at(a);
    cx = int(s.x) >> level;
    cy = int(s.y) >> level;
    const float x0 = float(cx << level), y0 = float(cy << level), size = float(1 << level);
    return std::min(1.0f, exit_fraction(seg, x0, x0 + size, y0, y0 + size));
  };
  int cx, cy, level = 0;
  float a = cell_exit(0, 0, cx, cy) + nudge;  // leave the pixel the ray starts in
  while (a <= 1 && r.steps < max_steps) {
    ++r.steps;
    if (!on_film(seg.at(a), g.width, g.height)) return r;
    const float a_exit = cell_exit(a, level, cx, cy);
    const float za = seg.z_at(a), ze = seg.z_at(a_exit);
    const float zc = hiz.at(level, cx, cy);
    if (std::max(za, ze) < zc) {  // in front of everything the cell shows: skip it, widen the step
      a = a_exit + nudge;
      level = std::min(level + 1, top);
      continue;
    }
    if (level > 0) {  // may pass behind something in this cell: look closer
      --level;
      continue;
    }
    // One pixel whose surface the ray reaches: a hit if it passes through the slab behind it and
    // arrives on the seen side. A ray leaving the surface instead -- still in front of its tangent
    // plane where it leaves the pixel, as a ray reflected at a grazing angle is over the surface it
    // started from, whose depth changes across one pixel more than the ray rises -- goes on.
    if (std::min(za, ze) <= zc * (1 + thickness)) {
      const GSurface sf = g.at(cx, cy);
      if (!faces_ray(sf, d)) {
        const Vec3 seen = dot(sf.ng, sf.wo) >= 0 ? sf.ng : -sf.ng;
        if (dot(seg.point_at(a_exit) - sf.p, seen) > 0) {
          a = a_exit + nudge;
          continue;
        }
        return r;  // entered the back of something
      }
      r.hit = true;
      r.x = cx;
      r.y = cy;
      return r;
    }
    a = a_exit + nudge;  // behind the slab: the ray passes under this surface
  }
  return r;
}

}  // namespace rl
