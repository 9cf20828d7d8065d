#include "backends/bvh_queries.h"

#include <algorithm>

#include "backends/bvh_traverse.h"
#include "core/parallel.h"

namespace rl {

namespace {
constexpr size_t kChunk = 256;
template <class Fn>
void parallel_chunks(size_t n, const Fn& fn) {
  parallel_for(int((n + kChunk - 1) / kChunk), [&](int c) { fn(size_t(c) * kChunk, std::min(n, size_t(c + 1) * kChunk)); });
}
}  // namespace

void BvhQueries::intersect_batch(std::span<const Ray> rays, std::span<Hit> hits, bool) const {
  const BvhView view = bvh_.view();
  parallel_chunks(rays.size(), [&](size_t a, size_t b) {
    for (size_t i = a; i < b; ++i) {
      hits[i] = Hit{};
      bvh_trace(view, rays[i], false, &hits[i]);
    }
  });
}

void BvhQueries::occluded_batch(std::span<const Ray> rays, std::span<uint8_t> blocked) const {
  const BvhView view = bvh_.view();
  parallel_chunks(rays.size(), [&](size_t a, size_t b) {
    for (size_t i = a; i < b; ++i) blocked[i] = bvh_trace(view, rays[i], true, nullptr) ? 1 : 0;
  });
}

}  // namespace rl
