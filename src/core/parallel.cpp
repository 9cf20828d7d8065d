#include "core/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <mutex>

namespace rl {

void parallel_for_tiles(int width, int height, const std::function<void(int, int, int, int)>& fn,
                        const std::function<void(int, int)>& progress) {
  constexpr int kTile = kPixelTile;
  const int tiles_x = (width + kTile - 1) / kTile, tiles_y = (height + kTile - 1) / kTile;
  const int tiles = tiles_x * tiles_y;
  std::atomic<int> done{0};
  std::mutex progress_mutex;
  tbb::parallel_for(tbb::blocked_range<int>(0, tiles, 1), [&](const tbb::blocked_range<int>& r) {
    for (int t = r.begin(); t < r.end(); ++t) {
      int tx = t % tiles_x, ty = t / tiles_x;
      fn(tx * kTile, ty * kTile, std::min(width, (tx + 1) * kTile), std::min(height, (ty + 1) * kTile));
      int d = ++done;
      if (progress) {
        std::unique_lock lock(progress_mutex, std::try_to_lock);
        if (lock.owns_lock() || d == tiles) {
          if (!lock.owns_lock()) lock.lock();
          progress(d, tiles);
        }
      }
    }
  });
}

void parallel_for_pixels(int width, int height, const std::function<void(int, int)>& fn,
                         const std::function<void(int, int)>& progress) {
  parallel_for_tiles(width, height, [&](int x0, int y0, int x1, int y1) {
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) fn(x, y);
  }, progress);
}

void parallel_for(int n, const std::function<void(int)>& fn) {
  tbb::parallel_for(tbb::blocked_range<int>(0, n, 1), [&](const tbb::blocked_range<int>& r) {
    for (int i = r.begin(); i < r.end(); ++i) fn(i);
  });
}

ThreadLimit::ThreadLimit(int threads) {
  if (threads > 0)
    control_ = new tbb::global_control(tbb::global_control::max_allowed_parallelism, size_t(threads));
}

ThreadLimit::~ThreadLimit() { delete static_cast<tbb::global_control*>(control_); }

}  // namespace rl
