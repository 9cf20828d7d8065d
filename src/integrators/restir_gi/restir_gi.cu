// ReSTIR GI's frame (restir_gi_frame.h) on the CUDA backend: one kernel per stage.
#include "frame/cuda_backend.cuh"
#include "integrators/restir_gi/restir_gi_frame.h"

namespace rl {

std::unique_ptr<Integrator> make_restir_gi_cuda(const RenderContext& ctx) { return make_on_cuda<RestirGiFrame>(ctx); }

}  // namespace rl
