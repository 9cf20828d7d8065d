// ReSTIR DI's, GI's and PT's frames (di_frame.h, gi_frame.h, pt_frame.h) on the host: the CUDA backend's drivers with
// the host execution policy, for tests on machines without a GPU (restir_cuda.h).
#include <stdexcept>
#include <string>

#include "backends/cpu/host_exec.h"
#include "integrators/restir_di/restir_di_frame.h"
#include "integrators/restir_gi/restir_gi_frame.h"
#include "integrators/restir_pt/restir_pt_frame.h"
#include "frame/restir_cuda.h"

namespace rl {

void check_frame_supported(const RenderContext& ctx, const char* integrator) {
  if (scene_animated(ctx.scene))
    throw std::runtime_error(std::string(integrator) +
                             " runs on the CUDA backend for static scenes only so far (this scene is animated: use render.backend = cpu)");
  if (ctx.planted) throw std::runtime_error("planted biases are a CPU test harness: use render.backend = cpu");
}

std::unique_ptr<Integrator> make_host_twin_restir_di(const RenderContext& ctx) { return std::make_unique<DiFrameRenderer<HostExec>>(ctx); }
std::unique_ptr<Integrator> make_host_twin_restir_gi(const RenderContext& ctx) { return std::make_unique<GiFrameRenderer<HostExec>>(ctx); }
std::unique_ptr<Integrator> make_host_twin_restir_pt(const RenderContext& ctx) {
  return std::make_unique<PtFrameRenderer<HostExec>>(ctx, &make_host_twin_restir_di);
}

}  // namespace rl
