// ReSTIR DI's frame (restir_di_frame.h) on the CUDA backend: one kernel per stage.
#include "frame/cuda_backend.cuh"
#include "integrators/restir_di/restir_di_frame.h"

namespace rl {

std::unique_ptr<Integrator> make_restir_di_cuda(const RenderContext& ctx) { return make_on_cuda<RestirDiFrame>(ctx); }

}  // namespace rl
