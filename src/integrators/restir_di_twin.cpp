// ReSTIR DI's frame (di_frame.h) on the host: the CUDA backend's driver with the host execution
// policy, for tests on machines without a GPU (restir_di_cuda.h).
#include <stdexcept>

#include "backends/host_exec.h"
#include "integrators/di_frame.h"
#include "integrators/restir_di_cuda.h"

namespace rl {

void check_di_frame_supported(const RenderContext& ctx) {
  if (scene_animated(ctx.scene))
    throw std::runtime_error("restir-di runs on the CUDA backend for static scenes only so far (this scene is animated: use render.backend = cpu)");
  if (ctx.planted) throw std::runtime_error("planted biases are a CPU test harness: use render.backend = cpu");
}

std::unique_ptr<Integrator> make_host_twin_restir_di(const RenderContext& ctx) {
  check_di_frame_supported(ctx);
  return std::make_unique<DiFrameRenderer<HostExec>>(ctx);
}

}  // namespace rl
