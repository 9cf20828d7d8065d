// ReSTIR GI's registry entry (registry.cpp): the option checks, and its frame (restir_gi_frame.h)
// on the CPU backend and on the CUDA backend's host twin (render.backend = cpu-bvh); restir_gi.cu
// instantiates it for CUDA.
#include "frame/bvh_backend.h"
#include "frame/cpu_backend.h"
#include "frame/cuda_maker.h"
#include "frame/restir_cuda.h"
#include "integrators/restir_gi/restir_gi_frame.h"

namespace rl {

std::unique_ptr<Integrator> make_restir_gi(const RenderContext& ctx) {
  if (ctx.options.render.debug_view == DebugView::reconnection_depth)
    throw OptionError("render.debug_view: reconnection-depth belongs to restir-pt");
  switch (ctx.options.render.backend) {
    case Backend::cuda: return make_on_cuda(&make_cuda_restir_gi, ctx);
    case Backend::cpu_bvh: return std::make_unique<RestirGiFrame<HostBvhBackend>>(ctx);
    case Backend::cpu: break;
  }
  return std::make_unique<RestirGiFrame<CpuBackend>>(ctx);
}

}  // namespace rl
