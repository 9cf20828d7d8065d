// The CUDA backend of the frames (CUDA sources only): the BVH backend over device memory, one
// kernel per stage (bvh_backend.h). Each algorithm's <algo>.cu instantiates its frame with it.
#pragma once
#include "backends/cuda/cuda_exec.cuh"
#include "frame/bvh_backend.h"

namespace rl {

using CudaBackend = BvhBackend<cuda::CudaExec>;

}  // namespace rl
