// ReSTIR GI's frame (restir_gi_frame.h) on the CUDA backend: one kernel per stage.
#include "frame/cuda_backend.cuh"
#include "frame/restir_cuda.h"
#include "integrators/restir_gi/restir_gi_frame.h"

namespace rl {

std::unique_ptr<Integrator> make_cuda_restir_gi(const RenderContext& ctx) {
  cuda::check(cudaSetDevice(0), "selecting device 0");
  return std::make_unique<RestirGiFrame<CudaBackend>>(ctx);
}

}  // namespace rl
