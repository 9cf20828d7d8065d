// ReSTIR DI's frame (di_frame.h) on the GPU: the CUDA execution policy's kernels, one per stage.
#include "backends/cuda/cuda_exec.cuh"
#include "integrators/restir_di/restir_di_frame.h"
#include "frame/restir_cuda.h"

namespace rl {

std::unique_ptr<Integrator> make_cuda_restir_di(const RenderContext& ctx) {
  cuda::check(cudaSetDevice(0), "selecting device 0");
  return std::make_unique<DiFrameRenderer<cuda::CudaExec>>(ctx);
}

}  // namespace rl
