// An execution policy over host memory and threads: the host twin of cuda::CudaExec
// (cuda_exec.cuh), so that a driver written once for both -- its buffers, copies and per-pixel
// launches -- also runs, and is tested, on a machine without a GPU.
//   Exec::Store                 where uploaded views live (view_upload.h)
//   Exec::Array<T>              a growing buffer: data, capacity, reserve(n), swap(other)
//   Exec::zero / upload / download (buffer <-> host memory, n elements), copy (buffer -> buffer)
//   Exec::mirror(a, host, n)          the host array as the stages read it: itself here (no copy),
//                                     a copy in a on the device
//   Exec::for_pixels(w, h, f, what, progress)   f(x, y) for every pixel, all done on return
//                                     (progress(done, total) after each tile where the policy can)
//   Exec::for_each(n, f, what)        f(i) for i < n, all done on return
//   Exec::for_chunks(n, chunk, f, what)   f(a, b) over [0, n) in ranges of at most `chunk` (the
//                                     device: ranges of one), all done on return
//   Exec::select(n, keep, out, what)  writes the i < n with keep(i) to out[], returns how many: in
//                                     order here, in any order on a device (consumers read by owner)
//   Exec::kWaveItems                  how many work items a wavefront keeps in flight (its buffers)
//   Exec::kOnDevice, device_id()      whether the arrays are in a GPU's memory, and which GPU's
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstring>
#include <functional>
#include <memory>
#include <type_traits>
#include <utility>

#include "backends/view_upload.h"
#include "core/parallel.h"

namespace rl {

struct HostExec {
  using Store = HostStore;
  // Where the arrays live (Integrator::FrameBuffer): host memory.
  static constexpr bool kOnDevice = false;
  static int device_id() { return 0; }

  template <class T>
  struct Array {
    T* data = nullptr;
    size_t capacity = 0;
    void reserve(size_t n) {
      if (n <= capacity) return;
      mem_ = std::make_unique<T[]>(n);
      // Garbage, as cudaMalloc's memory is: all bits set (NaN in every float), so that a stage
      // reading what no stage wrote shows in the host twin's image instead of reading zeros.
      static_assert(std::is_trivially_copyable_v<T>);
      std::memset(static_cast<void*>(mem_.get()), 0xff, n * sizeof(T));
      data = mem_.get();
      capacity = n;
    }
    void swap(Array& o) {
      std::swap(mem_, o.mem_);
      std::swap(data, o.data);
      std::swap(capacity, o.capacity);
    }

   private:
    std::unique_ptr<T[]> mem_;
  };

  template <class T>
  static void zero(Array<T>& a, size_t n) {
    std::fill_n(a.data, n, T{});
  }
  template <class T>
  static void upload(Array<T>& a, const T* host, size_t n) {
    a.reserve(n);
    std::copy_n(host, n, a.data);
  }
  template <class T>
  static void download(T* host, const Array<T>& a, size_t n) {
    std::copy_n(a.data, n, host);
  }
  // dst's first n elements := src's (dst grown to n).
  template <class T>
  static void copy(Array<T>& dst, const Array<T>& src, size_t n) {
    dst.reserve(n);
    std::copy_n(src.data, n, dst.data);
  }
  template <class T>
  static const T* mirror(Array<T>&, const T* host, size_t n) {
    return n ? host : nullptr;
  }
  template <class F>
  static void for_pixels(int width, int height, const F& f, const char*, const std::function<void(int, int)>& progress = {}) {
    parallel_for_pixels(width, height, [&](int x, int y) { f(x, y); }, progress);
  }
  // 2^16 paths: their state stays in the caches.
  static constexpr size_t kWaveItems = size_t(1) << 16;

  template <class F>
  static void for_chunks(size_t n, size_t chunk, const F& f, const char*) {
    parallel_for_chunks(n, chunk, [&](size_t a, size_t b) { f(a, b); });
  }
  template <class Keep>
  static uint32_t select(size_t n, const Keep& keep, Array<uint32_t>& out, const char*) {
    out.reserve(n);
    uint32_t count = 0;
    for (size_t i = 0; i < n; ++i)
      if (keep(i)) out.data[count++] = uint32_t(i);
    return count;
  }
  template <class F>
  static void for_each(size_t n, const F& f, const char*) {
    parallel_for_chunks(n, 4096, [&](size_t a, size_t b) {
      for (size_t i = a; i < b; ++i) f(i);
    });
  }
};

}  // namespace rl
