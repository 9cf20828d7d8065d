// Spatial neighbour pattern: a golden-angle (Vogel) spiral on the disk, rotated per pixel and
// frame — a low-discrepancy set of offsets, so a few neighbours already cover the radius evenly.
#pragma once
#include "core/math.h"

namespace rl::restir {

// Offset of neighbour k of `count` within `radius` pixels; `rotation` in [0,1) turns the spiral.
RESTIR_HD inline Vec2 spatial_offset(int k, int count, float radius, float rotation) {
  constexpr float kGoldenAngle = 2.39996322972865332f;  // pi (3 - sqrt 5)
  const float r = radius * std::sqrt((float(k) + 0.5f) / float(count));
  const float phi = float(k) * kGoldenAngle + rotation * 2 * kPi;
  return {r * std::cos(phi), r * std::sin(phi)};
}

}  // namespace rl::restir
