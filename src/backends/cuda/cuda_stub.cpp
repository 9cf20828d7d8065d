// The CUDA backend's entry points in a build without it (RESTIR_CUDA=OFF): each says so.
#include <stdexcept>

#include "backends/cuda/cuda_queries.h"

namespace rl {

namespace {
constexpr const char* kNotBuilt =
    "this build has no CUDA backend (configure with -DRESTIR_CUDA=ON where the CUDA toolkit's nvcc is installed)";
}

bool cuda_backend_built() { return false; }
std::string cuda_unavailable_reason() { return kNotBuilt; }
std::string cuda_device_description() { return kNotBuilt; }
std::unique_ptr<RayQueries> make_cuda_queries(const Scene&, BvhLayout) { throw BackendError(kNotBuilt); }
CudaRayTiming cuda_time_rays(const Scene&, std::span<const Ray>, int, BvhLayout) { throw BackendError(kNotBuilt); }

}  // namespace rl
