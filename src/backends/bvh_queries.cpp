#include "backends/bvh_queries.h"

#include <algorithm>

#include "backends/bvh_traverse.h"
#include "core/parallel.h"

namespace rl {

namespace {
constexpr size_t kChunk = 256;  // rays per parallel task
}  // namespace

void BvhQueries::intersect_batch(std::span<const Ray> rays, std::span<Hit> hits, bool) const {
  const BvhView view = bvh_.view();
  parallel_for_chunks(rays.size(), kChunk, [&](size_t a, size_t b) {
    for (size_t i = a; i < b; ++i) {
      hits[i] = Hit{};
      bvh_trace(view, rays[i], false, &hits[i]);
    }
  });
}

void BvhQueries::occluded_batch(std::span<const Ray> rays, std::span<uint8_t> blocked) const {
  const BvhView view = bvh_.view();
  parallel_for_chunks(rays.size(), kChunk, [&](size_t a, size_t b) {
    for (size_t i = a; i < b; ++i) blocked[i] = bvh_trace(view, rays[i], true, nullptr) ? 1 : 0;
  });
}

}  // namespace rl
