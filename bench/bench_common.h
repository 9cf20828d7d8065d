// Shared by the benchmarks.
#pragma once
#include <fmt/format.h>

#include <algorithm>
#include <string>
#include <vector>

#include "integrators/stage_times.h"

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

}  // namespace rl::bench
