// An integrator's CUDA version for render.backend = cuda, its failure (no CUDA backend in this
// build, no device, a context the GPU drivers do not handle yet) turned into the one option error
// every integrator gives.
#pragma once
#include <memory>
#include <stdexcept>
#include <string>

#include "frame/integrator.h"

namespace rl {

inline std::unique_ptr<Integrator> make_on_cuda(std::unique_ptr<Integrator> (*make)(const RenderContext&), const RenderContext& ctx) {
  try {
    return make(ctx);
  } catch (const std::runtime_error& e) {
    throw OptionError(std::string("render.backend = cuda: ") + e.what());
  }
}

}  // namespace rl
