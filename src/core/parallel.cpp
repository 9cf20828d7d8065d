#include "core/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <mutex>

namespace rl {

namespace {
constexpr int kTile = 16;
}

void parallel_for_pixels(int width, int height, const std::function<void(int, int)>& fn,
                         const std::function<void(int, int)>& progress) {
  const int tiles_x = (width + kTile - 1) / kTile, tiles_y = (height + kTile - 1) / kTile;
  const int tiles = tiles_x * tiles_y;
  std::atomic<int> done{0};
  std::mutex progress_mutex;
  tbb::parallel_for(tbb::blocked_range<int>(0, tiles, 1), [&](const tbb::blocked_range<int>& r) {
    for (int t = r.begin(); t < r.end(); ++t) {
      int tx = t % tiles_x, ty = t / tiles_x;
      int x1 = std::min(width, (tx + 1) * kTile), y1 = std::min(height, (ty + 1) * kTile);
      for (int y = ty * kTile; y < y1; ++y)
        for (int x = tx * kTile; x < x1; ++x) fn(x, y);
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
