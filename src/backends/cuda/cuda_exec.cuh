// The CUDA execution policy (CUDA sources only): device buffers, copies, and one kernel launch per
// per-pixel stage. host_exec.h documents the interface and is its host twin.
#pragma once
#include <cuda_runtime.h>

#include "backends/cuda/device_store.cuh"

namespace rl::cuda {

// 16x8 threads: a block covers a compact patch of pixels, so neighbouring threads read
// neighbouring G-buffer entries and reservoirs (spatial reuse reads within a radius).
inline constexpr unsigned kPixelBlockX = 16, kPixelBlockY = 8, kItemBlock = 256;

template <class F>
__global__ void pixels_kernel(int width, int height, F f) {
  const int x = int(blockIdx.x * blockDim.x + threadIdx.x), y = int(blockIdx.y * blockDim.y + threadIdx.y);
  if (x < width && y < height) f(x, y);
}

template <class F>
__global__ void items_kernel(size_t n, F f) {
  const size_t i = size_t(blockIdx.x) * blockDim.x + threadIdx.x;
  if (i < n) f(i);
}

template <class F>
__global__ void ranges_kernel(size_t n, F f) {
  const size_t i = size_t(blockIdx.x) * blockDim.x + threadIdx.x;
  if (i < n) f(i, i + 1);
}

// Appends each i < n with keep(i) to out through one counter: the order depends on the schedule.
template <class Keep>
__global__ void select_kernel(size_t n, Keep keep, uint32_t* out, uint32_t* count) {
  const size_t i = size_t(blockIdx.x) * blockDim.x + threadIdx.x;
  if (i < n && keep(i)) out[atomicAdd(count, 1u)] = uint32_t(i);
}

struct CudaExec {
  using Store = DeviceStore;
  static constexpr bool kOnDevice = true;
  static int device_id() {
    int d = 0;
    check(cudaGetDevice(&d), "reading the current device");
    return d;
  }
  template <class T>
  using Array = DeviceArray<T>;

  template <class T>
  static void zero(Array<T>& a, size_t n) {
    if (n) check(cudaMemset(a.data, 0, n * sizeof(T)), "clearing device memory");
  }
  template <class T>
  static void upload(Array<T>& a, const T* host, size_t n) {
    a.reserve(n);
    if (n) check(cudaMemcpy(a.data, host, n * sizeof(T), cudaMemcpyHostToDevice), "copying to the device");
  }
  template <class T>
  static void download(T* host, const Array<T>& a, size_t n) {
    if (n) check(cudaMemcpy(host, a.data, n * sizeof(T), cudaMemcpyDeviceToHost), "copying from the device");
  }
  template <class T>
  static void copy(Array<T>& dst, const Array<T>& src, size_t n) {
    dst.reserve(n);
    if (n) check(cudaMemcpy(dst.data, src.data, n * sizeof(T), cudaMemcpyDeviceToDevice), "copying on the device");
  }
  template <class T>
  static const T* mirror(Array<T>& a, const T* host, size_t n) {
    upload(a, host, n);
    return n ? a.data : nullptr;
  }
  // Synchronous, so that the caller's StageTimer measures the stage and errors name it. No
  // progress reports: a launch covers the whole image.
  template <class F, class Progress = int>
  static void for_pixels(int width, int height, const F& f, const char* what, const Progress& = {}) {
    const dim3 threads(kPixelBlockX, kPixelBlockY);
    const dim3 blocks((unsigned(width) + kPixelBlockX - 1) / kPixelBlockX, (unsigned(height) + kPixelBlockY - 1) / kPixelBlockY);
    pixels_kernel<<<blocks, threads>>>(width, height, f);
    finish(what);
  }
  // 2^22 paths: a 1920x1080 frame at 1 spp in one wave, so that each bounce is one launch of each
  // stage (0.7 GB of path state, hits, shadow rays and lists).
  static constexpr size_t kWaveItems = size_t(1) << 22;

  template <class F>
  static void for_chunks(size_t n, size_t, const F& f, const char* what) {
    if (n == 0) return;
    ranges_kernel<<<unsigned((n + kItemBlock - 1) / kItemBlock), kItemBlock>>>(n, f);
    finish(what);
  }
  template <class Keep>
  static uint32_t select(size_t n, const Keep& keep, Array<uint32_t>& out, const char* what) {
    out.reserve(n + 1);  // the last entry holds the counter
    uint32_t* count = out.data + n;
    check(cudaMemset(count, 0, sizeof(uint32_t)), what);
    if (n) select_kernel<<<unsigned((n + kItemBlock - 1) / kItemBlock), kItemBlock>>>(n, keep, out.data, count);
    finish(what);
    uint32_t m = 0;
    check(cudaMemcpy(&m, count, sizeof(uint32_t), cudaMemcpyDeviceToHost), what);
    return m;
  }
  template <class F>
  static void for_each(size_t n, const F& f, const char* what) {
    if (n == 0) return;
    items_kernel<<<unsigned((n + kItemBlock - 1) / kItemBlock), kItemBlock>>>(n, f);
    finish(what);
  }
  static void finish(const char* what) {
    check(cudaGetLastError(), what);
    check(cudaDeviceSynchronize(), what);
  }
};

}  // namespace rl::cuda
