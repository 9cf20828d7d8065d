// make_cuda_path_tracer in a build without the CUDA backend (RESTIR_CUDA=OFF).
#include <stdexcept>

#include "backends/cuda/cuda_queries.h"
#include "integrators/path/path_tracer_cuda.h"

namespace rl {

std::unique_ptr<Integrator> make_cuda_path_tracer(const RenderContext&) { throw std::runtime_error(cuda_unavailable_reason()); }

}  // namespace rl
