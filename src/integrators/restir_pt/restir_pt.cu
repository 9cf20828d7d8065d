// ReSTIR PT's frame (restir_pt_frame.h) on the CUDA backend: one kernel per stage.
#include "frame/cuda_backend.cuh"
#include "frame/restir_cuda.h"
#include "integrators/restir_pt/restir_pt_frame.h"

namespace rl {

std::unique_ptr<Integrator> make_direct_light(const RenderContext& ctx);  // restir_pt.cpp

std::unique_ptr<Integrator> make_cuda_restir_pt(const RenderContext& ctx) {
  cuda::check(cudaSetDevice(0), "selecting device 0");
  return std::make_unique<RestirPtFrame<CudaBackend>>(ctx, make_direct_light(ctx));
}

}  // namespace rl
