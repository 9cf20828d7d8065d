// The path tracer's frame (path_frame.h) on the CUDA backend: one kernel per stage.
#include "frame/cuda_backend.cuh"
#include "integrators/path/path_frame.h"
#include "integrators/path/path_tracer_cuda.h"

namespace rl {

std::unique_ptr<Integrator> make_cuda_path_tracer(const RenderContext& ctx) {
  cuda::check(cudaSetDevice(0), "selecting device 0");
  return std::make_unique<PathFrame<CudaBackend>>(ctx);
}

}  // namespace rl
