// The ReSTIR frames on the CUDA backend (render.backend = cuda): each algorithm's <algo>.cu
// instantiates its frame with CudaBackend (cuda_backend.cuh). A plain host header: no CUDA type
// crosses it.
#pragma once
#include <memory>

#include "frame/integrator.h"

namespace rl {

// Throw std::runtime_error naming the reason when the build has no CUDA backend or no device.
std::unique_ptr<Integrator> make_cuda_restir_di(const RenderContext& ctx);
std::unique_ptr<Integrator> make_cuda_restir_gi(const RenderContext& ctx);
std::unique_ptr<Integrator> make_cuda_restir_pt(const RenderContext& ctx);

}  // namespace rl
