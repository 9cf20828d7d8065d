// Two ray-query backends' answers to the same rays, compared ray by ray (tests/backends: the
// project's BVH against Embree, the wide tree against the binary one): hit or miss and occlusion
// are counted here; where both hit, the caller's `judge` weighs the two hits (a distance, a
// primitive, barycentrics) and adds to t_mismatch or ties.
#pragma once
#include <cstdint>
#include <vector>

#include "scene/ray_queries.h"

namespace rl::test {

struct QueryAgreement {
  size_t rays = 0, hits = 0, hit_mismatch = 0, t_mismatch = 0, ties = 0, occluded_mismatch = 0;
};

// judge(i, reference hit, other hit, agreement) for each ray both answer with a hit.
template <class Judge>
QueryAgreement compare_queries(const RayQueries& reference, const RayQueries& other, const std::vector<Ray>& rays, Judge&& judge) {
  std::vector<Hit> a(rays.size()), b(rays.size());
  std::vector<uint8_t> oa(rays.size()), ob(rays.size());
  reference.intersect_batch(rays, a);
  other.intersect_batch(rays, b);
  reference.occluded_batch(rays, oa);
  other.occluded_batch(rays, ob);
  QueryAgreement g;
  g.rays = rays.size();
  for (size_t i = 0; i < rays.size(); ++i) {
    g.hits += a[i].valid();
    g.occluded_mismatch += oa[i] != ob[i];
    if (a[i].valid() != b[i].valid()) {
      ++g.hit_mismatch;
      continue;
    }
    if (a[i].valid()) judge(i, a[i], b[i], g);
  }
  return g;
}

}  // namespace rl::test
