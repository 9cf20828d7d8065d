// make_cuda_restir_di in a build without the CUDA backend (RESTIR_CUDA=OFF).
#include <stdexcept>

#include "backends/cuda/cuda_queries.h"
#include "frame/restir_cuda.h"

namespace rl {

std::unique_ptr<Integrator> make_cuda_restir_di(const RenderContext&) { throw std::runtime_error(cuda_unavailable_reason()); }

}  // namespace rl
