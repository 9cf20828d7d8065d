// Random rays through a scene, for comparing ray-query backends (tests/backends/test_bvh.cpp on the CPU,
// tests/gpu/test_gpu.cpp on a GPU).
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/rng.h"
#include "scene/scene.h"

namespace rl::test {

// Rays from points spread over the scene's box (a margin around it) in uniform directions; every
// other ray is cut short at a random fraction of the box's diagonal, so any-hit queries both hit
// and miss. Deterministic.
inline std::vector<Ray> random_rays(const Scene& scene, size_t n, uint64_t seed) {
  Bounds3 b = scene.bounds();
  const Vec3 margin = b.diagonal() * 0.1f;
  b.lo -= margin, b.hi += margin;
  Pcg32 rng(seed);
  std::vector<Ray> rays(n);
  for (size_t i = 0; i < n; ++i) {
    const Vec3 u{rng.next_float(), rng.next_float(), rng.next_float()};
    rays[i].o = b.lo + b.diagonal() * u;
    const float z = 1 - 2 * rng.next_float(), phi = 2 * kPi * rng.next_float(), r = std::sqrt(std::max(0.0f, 1 - z * z));
    rays[i].d = {r * std::cos(phi), r * std::sin(phi), z};
    if (i % 2) rays[i].tmax = length(b.diagonal()) * rng.next_float();
  }
  return rays;
}

}  // namespace rl::test
