// Shared by the benchmarks.
#pragma once
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include "core/parallel.h"
#include "integrators/stage_times.h"
#include "scene/accel.h"

namespace rl::bench {

// Median of the values after the first `skip` (e.g. a warm-up frame or one without history).
inline double median(std::vector<double> v, size_t skip = 0) {
  if (v.size() > skip) v.erase(v.begin(), v.begin() + long(skip));
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

// "stage a.b ms, stage c.d ms, ...": the median of each stage over the frames after `skip`.
inline std::string stage_summary(const std::vector<StageTimes>& frames, size_t skip = 0) {
  std::string out;
  for (const std::string& name : stage_names(frames)) {
    std::vector<double> v;
    for (const StageTimes& f : frames) v.push_back(f.of(name));
    out += fmt::format("{}{} {:.1f} ms", out.empty() ? "" : ", ", name, median(v, skip));
  }
  return out;
}

// Seconds Embree alone takes to answer `rays` (closest hit) and `shadow` (any hit) with the
// scalar queries the renderer issues, over all cores in chunks of 4096 rays: the rays' own cost.
inline double replay(const Accel& accel, const std::vector<Ray>& rays, const std::vector<Ray>& shadow) {
  const int chunk = 4096;
  const int n1 = int((rays.size() + chunk - 1) / chunk), n2 = int((shadow.size() + chunk - 1) / chunk);
  const auto t0 = std::chrono::steady_clock::now();
  parallel_for(n1 + n2, [&](int c) {
    if (c < n1) {
      const size_t end = std::min(rays.size(), size_t(c + 1) * chunk);
      for (size_t i = size_t(c) * chunk; i < end; ++i) {
        Hit h;
        (void)accel.intersect(rays[i], h);
      }
    } else {
      const size_t b = size_t(c - n1) * chunk, end = std::min(shadow.size(), b + chunk);
      for (size_t i = b; i < end; ++i) (void)accel.occluded(shadow[i]);
    }
  });
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace rl::bench
