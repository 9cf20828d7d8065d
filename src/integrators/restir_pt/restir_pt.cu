// ReSTIR PT's frame (pt_frame.h) on the GPU: the CUDA execution policy's kernels, one per stage;
// with pt.direct = restir-di, the CUDA ReSTIR DI (restir_di_cuda.cu) adds the direct light.
#include "backends/cuda/cuda_exec.cuh"
#include "integrators/restir_pt/restir_pt_frame.h"
#include "frame/restir_cuda.h"

namespace rl {

std::unique_ptr<Integrator> make_cuda_restir_pt(const RenderContext& ctx) {
  cuda::check(cudaSetDevice(0), "selecting device 0");
  return std::make_unique<PtFrameRenderer<cuda::CudaExec>>(ctx, &make_cuda_restir_di);
}

}  // namespace rl
