// ReSTIR DI's registry entry (registry.cpp): its option checks, and its frame (restir_di_frame.h)
// on the host backends; restir_di.cu instantiates it for CUDA.
#include "frame/bvh_backend.h"
#include "integrators/restir_di/restir_di_frame.h"

namespace rl {

void check_restir_di(const RenderContext& ctx) { refuse_reconnection_depth(ctx, " (DI samples have no path)"); }

std::unique_ptr<Integrator> make_restir_di(const RenderContext& ctx) { return make_on_host<RestirDiFrame>(ctx); }

}  // namespace rl
