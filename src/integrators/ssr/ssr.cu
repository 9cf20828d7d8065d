// The ssr frame (ssr_frame.h) on the CUDA backend: one kernel per stage.
#include "frame/cuda_backend.cuh"
#include "integrators/ssr/ssr_frame.h"

namespace rl {

std::unique_ptr<Integrator> make_ssr_cuda(const RenderContext& ctx) { return make_on_cuda<SsrFrame>(ctx); }

}  // namespace rl
