// Shared by the benchmarks.
#pragma once
#include <algorithm>
#include <vector>

namespace rl::bench {

// Median of the values after the first `skip` (e.g. a warm-up frame or one without history).
inline double median(std::vector<double> v, size_t skip = 0) {
  if (v.size() > skip) v.erase(v.begin(), v.begin() + long(skip));
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace rl::bench
