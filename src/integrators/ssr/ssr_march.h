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
// side's).
#pragma once
#include <vector>

#include "frame/gbuffer.h"
#include "scene/camera.h"

namespace rl {

// Nearest view depth (distance along the camera's forward axis) per cell: level 0 is one value
// per pixel (+inf where the primary ray escaped), level l covers 2^l x 2^l pixels.
struct HiZPyramid {
  struct Level {
    int width = 0, height = 0;
    std::vector<float> z;
    float at(int x, int y) const { return z[size_t(y) * size_t(width) + size_t(x)]; }
  };
  std::vector<Level> levels;
  void build(const PerspectiveCamera& camera, const GBuffer& g);
};

struct MarchResult {
  bool hit = false;
  int x = 0, y = 0;  // the pixel the ray landed on
  int steps = 0;     // probes (linear) or cells visited (Hi-Z)
};

// The ray (o, d), at most max_distance long, through the G-buffer g of `camera`; hiz must have
// been built from the same camera and g.
MarchResult march_linear(const PerspectiveCamera& camera, const GBuffer& g, const HiZPyramid& hiz, Vec3 o, Vec3 d,
                         float max_distance, int max_steps, float thickness);
MarchResult march_hiz(const PerspectiveCamera& camera, const GBuffer& g, const HiZPyramid& hiz, Vec3 o, Vec3 d,
                      float max_distance, int max_steps, float thickness);

}  // namespace rl
