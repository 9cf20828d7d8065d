// CUDA ray queries: the BVH in device memory, one thread per ray, one launch per batch.
#include <cuda_runtime.h>

#include <algorithm>
#include <mutex>
#include <vector>
#include <stdexcept>
#include <string>

#include "backends/bvh.h"
#include "backends/bvh_traverse.h"
#include "backends/view_upload.h"
#include "backends/cuda/cuda_queries.h"
#include "backends/cuda/device_store.cuh"

namespace rl {

namespace {

using cuda::check;
using cuda::DeviceArray;

__global__ void intersect_kernel(BvhView bvh, const Ray* rays, Hit* hits, uint32_t n) {
  const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  Hit h;
  bvh_trace(bvh, rays[i], false, &h);
  hits[i] = h;
}

__global__ void occluded_kernel(BvhView bvh, const Ray* rays, uint8_t* blocked, uint32_t n) {
  const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  blocked[i] = bvh_trace(bvh, rays[i], true, nullptr) ? 1 : 0;
}

constexpr uint32_t kBlock = 128;  // threads per block: short traversal stacks, many warps in flight

class CudaQueries final : public RayQueries {
 public:
  CudaQueries(const Scene& scene, BvhLayout layout) : scene_(scene), layout_(layout) {
    check(cudaSetDevice(0), "selecting device 0");
    check(cudaStreamCreateWithFlags(&stream_, cudaStreamNonBlocking), "creating a stream");
    upload_bvh();
  }
  ~CudaQueries() override {
    if (stream_) cudaStreamDestroy(stream_);
  }

  void intersect_batch(std::span<const Ray> rays, std::span<Hit> hits, bool) const override {
    if (rays.empty()) return;
    std::lock_guard lock(mutex_);  // one batch at a time: they share the device arrays
    rays_.upload(rays.data(), rays.size(), stream_);
    hits_.reserve(rays.size());
    const uint32_t n = uint32_t(rays.size());
    intersect_kernel<<<(n + kBlock - 1) / kBlock, kBlock, 0, stream_>>>(view_, rays_.data, hits_.data, n);
    check(cudaGetLastError(), "launching the closest-hit kernel");
    check(cudaMemcpyAsync(hits.data(), hits_.data, n * sizeof(Hit), cudaMemcpyDeviceToHost, stream_), "copying hits back");
    check(cudaStreamSynchronize(stream_), "tracing closest hits");
  }

  void occluded_batch(std::span<const Ray> rays, std::span<uint8_t> blocked) const override {
    if (rays.empty()) return;
    std::lock_guard lock(mutex_);
    rays_.upload(rays.data(), rays.size(), stream_);
    blocked_.reserve(rays.size());
    const uint32_t n = uint32_t(rays.size());
    occluded_kernel<<<(n + kBlock - 1) / kBlock, kBlock, 0, stream_>>>(view_, rays_.data, blocked_.data, n);
    check(cudaGetLastError(), "launching the any-hit kernel");
    check(cudaMemcpyAsync(blocked.data(), blocked_.data, n, cudaMemcpyDeviceToHost, stream_), "copying occlusion back");
    check(cudaStreamSynchronize(stream_), "tracing shadow rays");
  }

  // An animated scene moved: a fresh SAH build of its new pose (refitting would keep the old
  // topology, which degrades as objects move apart), uploaded once per frame.
  void update() override {
    std::lock_guard lock(mutex_);
    upload_bvh();
  }
  const char* backend_name() const override { return "cuda"; }

 private:
  void upload_bvh() {
    bvh_store_.clear();
    view_ = store_bvh_view(bvh_store_, build_bvh(scene_, layout_));
  }

  const Scene& scene_;
  BvhLayout layout_;
  cudaStream_t stream_ = nullptr;
  cuda::DeviceStore bvh_store_;
  BvhView view_;
  mutable std::mutex mutex_;
  mutable DeviceArray<Ray> rays_;
  mutable DeviceArray<Hit> hits_;
  mutable DeviceArray<uint8_t> blocked_;
};

}  // namespace

bool cuda_backend_built() { return true; }

std::string cuda_unavailable_reason() {
  int count = 0;
  const cudaError_t e = cudaGetDeviceCount(&count);
  if (e != cudaSuccess) return std::string("no usable CUDA device: ") + cudaGetErrorString(e);
  if (count == 0) return "no CUDA device found";
  return {};
}

std::string cuda_device_description() {
  if (std::string why = cuda_unavailable_reason(); !why.empty()) return why;
  cudaDeviceProp p{};
  if (cudaGetDeviceProperties(&p, 0) != cudaSuccess) return "device 0: properties unavailable";
  return std::string(p.name) + ", " + std::to_string(p.totalGlobalMem >> 30) + " GiB, sm_" + std::to_string(p.major) +
         std::to_string(p.minor) + ", " + std::to_string(p.multiProcessorCount) + " SMs";
}

std::unique_ptr<RayQueries> make_cuda_queries(const Scene& scene, BvhLayout layout) {
  if (std::string why = cuda_unavailable_reason(); !why.empty()) throw BackendError(why);
  return std::make_unique<CudaQueries>(scene, layout);
}

CudaRayTiming cuda_time_rays(const Scene& scene, std::span<const Ray> rays, int repeats, BvhLayout layout) {
  if (std::string why = cuda_unavailable_reason(); !why.empty()) throw BackendError(why);
  check(cudaSetDevice(0), "selecting device 0");
  cuda::DeviceStore store;
  const BvhView view = store_bvh_view(store, build_bvh(scene, layout));
  DeviceArray<Ray> d_rays;
  DeviceArray<Hit> d_hits;
  DeviceArray<uint8_t> d_blocked;
  CudaRayTiming t;
  const uint32_t n = uint32_t(rays.size());
  if (n == 0) return t;  // no launch of zero blocks
  d_hits.reserve(n);
  d_blocked.reserve(n);
  cudaEvent_t start, stop;
  check(cudaEventCreate(&start), "creating an event");
  check(cudaEventCreate(&stop), "creating an event");
  auto elapsed = [&] {
    check(cudaEventSynchronize(stop), "timing");
    float ms = 0;
    check(cudaEventElapsedTime(&ms, start, stop), "timing");
    return double(ms);
  };
  check(cudaEventRecord(start), "timing");
  d_rays.upload(rays.data(), n, nullptr);
  check(cudaEventRecord(stop), "timing");
  t.upload_ms = elapsed();
  const uint32_t blocks = (n + kBlock - 1) / kBlock;
  t.closest_ms = t.any_ms = 1e30;
  for (int r = 0; r < std::max(1, repeats); ++r) {
    check(cudaEventRecord(start), "timing");
    intersect_kernel<<<blocks, kBlock>>>(view, d_rays.data, d_hits.data, n);
    check(cudaEventRecord(stop), "timing");
    t.closest_ms = std::min(t.closest_ms, elapsed());
    check(cudaEventRecord(start), "timing");
    occluded_kernel<<<blocks, kBlock>>>(view, d_rays.data, d_blocked.data, n);
    check(cudaEventRecord(stop), "timing");
    t.any_ms = std::min(t.any_ms, elapsed());
  }
  check(cudaGetLastError(), "running the traversal kernels");
  std::vector<Hit> hits(n);
  check(cudaMemcpy(hits.data(), d_hits.data, n * sizeof(Hit), cudaMemcpyDeviceToHost), "copying hits back");
  for (const Hit& h : hits) t.hits += h.valid();
  cudaEventDestroy(start);
  cudaEventDestroy(stop);
  return t;
}

}  // namespace rl
