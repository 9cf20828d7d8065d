// ReSTIR GI's registry entry (registry.cpp): its option checks, and its frame (restir_gi_frame.h)
// on the host backends; restir_gi.cu instantiates it for CUDA.
#include "frame/bvh_backend.h"
#include "integrators/restir_gi/restir_gi_frame.h"

namespace rl {

void check_restir_gi(const RenderContext& ctx) { refuse_reconnection_depth(ctx, " (GI samples keep no path)"); }

std::unique_ptr<Integrator> make_restir_gi(const RenderContext& ctx) { return make_on_host<RestirGiFrame>(ctx); }

}  // namespace rl
