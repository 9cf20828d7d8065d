// The CUDA backend of the frames (CUDA sources only): the BVH backend over device memory, one
// kernel per stage (bvh_backend.h). Each algorithm's <algo>.cu instantiates its frame with it.
#pragma once
#include <memory>
#include <utility>

#include "backends/cuda/cuda_exec.cuh"
#include "frame/bvh_backend.h"

namespace rl {

using CudaBackend = BvhBackend<cuda::CudaExec>;

// An algorithm's frame on device 0: what its registry row's `make_cuda` returns (registry.cpp).
// Throws BackendError naming what failed (no device, too little memory).
template <template <class> class Frame, class... Args>
std::unique_ptr<Integrator> make_on_cuda(const RenderContext& ctx, Args&&... args) {
  cuda::check(cudaSetDevice(0), "selecting device 0");
  return std::make_unique<Frame<CudaBackend>>(ctx, std::forward<Args>(args)...);
}

}  // namespace rl
