// The one parallel loop of the renderer: tiles of pixels over oneTBB. Work is split into fixed
// tiles so that results never depend on the thread count (each pixel owns its random streams).
#pragma once
#include <algorithm>
#include <cstddef>
#include <functional>

namespace rl {

// The side of the fixed square tiles the pixel loops split an image into.
inline constexpr int kPixelTile = 16;

// Calls fn(x0, y0, x1, y1) for every tile -- pixels [x0, x1) x [y0, y1), kPixelTile square, clipped
// to the image -- on TBB worker threads; progress(done, total) is called from one thread at a time
// after each finished tile (may be empty). For stages that batch a tile's work (its camera rays).
void parallel_for_tiles(int width, int height, const std::function<void(int, int, int, int)>& fn,
                        const std::function<void(int, int)>& progress = {});
// Calls fn(x, y) for every pixel, tile by tile (parallel_for_tiles).
void parallel_for_pixels(int width, int height, const std::function<void(int, int)>& fn,
                         const std::function<void(int, int)>& progress = {});
// Calls fn(i) for i in [0, n) in parallel.
void parallel_for(int n, const std::function<void(int)>& fn);

// Calls fn(first, end) for the chunks [0, chunk), [chunk, 2 chunk), ... of [0, n) in parallel: the
// batched loops of the wavefront (rays, paths) over flat buffers.
template <class Fn>
void parallel_for_chunks(size_t n, size_t chunk, const Fn& fn) {
  parallel_for(int((n + chunk - 1) / chunk), [&](int c) { fn(size_t(c) * chunk, std::min(n, size_t(c + 1) * chunk)); });
}

// Limits the worker threads of every parallel loop for the lifetime of the object (0 = all cores).
class ThreadLimit {
 public:
  explicit ThreadLimit(int threads);
  ~ThreadLimit();
  ThreadLimit(const ThreadLimit&) = delete;
  ThreadLimit& operator=(const ThreadLimit&) = delete;

 private:
  void* control_ = nullptr;
};

}  // namespace rl
