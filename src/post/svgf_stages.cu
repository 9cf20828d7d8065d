// SVGF's per-pixel stages (svgf_driver.h) on the CUDA backend: one kernel per stage, the math of
// svgf_stages.h that Svgf runs on the CPU. Compiled with --fmad=false (CMakeLists.txt): without
// fused multiply-adds, IEEE division and square root (nvcc's defaults) and the polynomial exp_neg,
// the device computes Svgf's floats (tests/gpu/test_gpu_svgf.cpp); a sigma_n that is not a power
// of two is the exception (powf on the device, std::pow on the host).
#include "backends/cuda/cuda_exec.cuh"
#include "post/svgf_driver.h"

namespace rl {

std::unique_ptr<SvgfFilter> make_svgf_cuda(const DenoiseOptions& o) {
  cuda::check(cudaSetDevice(0), "selecting device 0");
  return std::make_unique<SvgfStages<cuda::CudaExec>>(o);
}

}  // namespace rl
