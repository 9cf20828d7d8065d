// ReSTIR PT's frame (restir_pt_frame.h) on the CUDA backend: one kernel per stage.
#include "frame/cuda_backend.cuh"
#include "integrators/restir_pt/restir_pt_frame.h"

namespace rl {

std::unique_ptr<Integrator> make_direct_light(const RenderContext& ctx);  // restir_pt.cpp

std::unique_ptr<Integrator> make_restir_pt_cuda(const RenderContext& ctx) { return make_on_cuda<RestirPtFrame>(ctx, make_direct_light(ctx)); }

}  // namespace rl
