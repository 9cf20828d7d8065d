// The ssr integrator's registry entry (registry.cpp): its option check, and its frame (ssr_frame.h)
// on the host backends; ssr.cu instantiates it for CUDA.
#include "frame/bvh_backend.h"
#include "integrators/ssr/ssr_frame.h"

namespace rl {

void check_ssr(const RenderContext& ctx) { refuse_debug_views(ctx, "ssr has no debug views (they belong to the ReSTIR integrators)"); }

std::unique_ptr<Integrator> make_ssr(const RenderContext& ctx) { return make_on_host<SsrFrame>(ctx); }

}  // namespace rl
