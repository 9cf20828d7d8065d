// ReSTIR DI's registry entry (registry.cpp): the option checks, and its frame (restir_di_frame.h)
// on the CPU backend and on the CUDA backend's host twin (render.backend = cpu-bvh); restir_di.cu
// instantiates it for CUDA.
#include "frame/bvh_backend.h"
#include "frame/cpu_backend.h"
#include "frame/cuda_maker.h"
#include "frame/restir_cuda.h"
#include "integrators/restir_di/restir_di_frame.h"

namespace rl {

std::unique_ptr<Integrator> make_restir_di(const RenderContext& ctx) {
  if (ctx.options.render.debug_view == DebugView::reconnection_depth)
    throw OptionError("render.debug_view: reconnection-depth belongs to restir-pt (DI samples have no path)");
  switch (ctx.options.render.backend) {
    case Backend::cuda: return make_on_cuda(&make_cuda_restir_di, ctx);
    case Backend::cpu_bvh: return std::make_unique<RestirDiFrame<HostBvhBackend>>(ctx);
    case Backend::cpu: break;
  }
  return std::make_unique<RestirDiFrame<CpuBackend>>(ctx);
}

}  // namespace rl
