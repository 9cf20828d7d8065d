// The error type of the ray-query backends: Embree (cpu, cpu-bvh) and the CUDA device.
#pragma once
#include <stdexcept>

namespace rl {

// A backend that cannot do its work: Embree failing, no CUDA device or backend, a CUDA call failing.
struct BackendError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace rl
