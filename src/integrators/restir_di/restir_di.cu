// ReSTIR DI's frame (restir_di_frame.h) on the CUDA backend: one kernel per stage.
#include "frame/cuda_backend.cuh"
#include "frame/restir_cuda.h"
#include "integrators/restir_di/restir_di_frame.h"

namespace rl {

std::unique_ptr<Integrator> make_cuda_restir_di(const RenderContext& ctx) {
  cuda::check(cudaSetDevice(0), "selecting device 0");
  return std::make_unique<RestirDiFrame<CudaBackend>>(ctx);
}

}  // namespace rl
