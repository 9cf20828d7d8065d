// The path tracer's frame (path_frame.h) on the CUDA backend: one kernel per stage.
#include "frame/cuda_backend.cuh"
#include "integrators/path/path_frame.h"

namespace rl {

std::unique_ptr<Integrator> make_path_tracer_cuda(const RenderContext& ctx) { return make_on_cuda<PathFrame>(ctx); }

}  // namespace rl
