// Device memory for the CUDA backend's kernels (CUDA sources only): checked calls, a growing
// array reused across batches, and a store that owns many uploaded arrays and frees them together.
#pragma once
#include <cuda_runtime.h>

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "backends/backend_error.h"

namespace rl::cuda {

inline void check(cudaError_t e, const char* what) {
  if (e != cudaSuccess) throw BackendError(std::string("CUDA error while ") + what + ": " + cudaGetErrorString(e));
}

// A device array that grows and never shrinks: batches and frames reuse it (ARCHITECTURE.md:
// buffers are allocated once per size, not per pass).
template <class T>
struct DeviceArray {
  T* data = nullptr;
  size_t capacity = 0;
  DeviceArray() = default;
  DeviceArray(const DeviceArray&) = delete;
  DeviceArray& operator=(const DeviceArray&) = delete;
  ~DeviceArray() {
    if (data) cudaFree(data);
  }
  void reserve(size_t n) {
    if (n <= capacity) return;
    if (data) cudaFree(data);
    data = nullptr, capacity = 0;
    check(cudaMalloc(&data, n * sizeof(T)), "allocating device memory");
    capacity = n;
  }
  // Exchanges the two arrays' memory (a pass's output becomes its input).
  void swap(DeviceArray& o) {
    std::swap(data, o.data);
    std::swap(capacity, o.capacity);
  }
  void upload(const T* host, size_t n, cudaStream_t s) {
    reserve(n);
    if (n) check(cudaMemcpyAsync(data, host, n * sizeof(T), cudaMemcpyHostToDevice, s), "copying to the device");
  }
};

// Uploaded arrays that live as long as the store (a scene's device copy).
class DeviceStore {
 public:
  DeviceStore() = default;
  DeviceStore(const DeviceStore&) = delete;
  DeviceStore& operator=(const DeviceStore&) = delete;
  ~DeviceStore() { clear(); }
  void clear() {
    for (void* p : owned_) cudaFree(p);
    owned_.clear();
  }
  // A device copy of host[0, n) (null for n == 0 or a null host pointer).
  template <class T>
  T* upload(const T* host, size_t n) {
    if (!host || n == 0) return nullptr;
    void* p = nullptr;
    check(cudaMalloc(&p, n * sizeof(T)), "allocating device memory");
    owned_.push_back(p);
    check(cudaMemcpy(p, host, n * sizeof(T), cudaMemcpyHostToDevice), "copying to the device");
    return static_cast<T*>(p);
  }
  template <class T>
  T* upload(const std::vector<T>& v) {
    return upload(v.data(), v.size());
  }

 private:
  std::vector<void*> owned_;
};

}  // namespace rl::cuda
