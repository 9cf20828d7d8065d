// The post-process stage's interface (ARCHITECTURE.md: src/post/ holds the denoisers, run over a
// finished frame, never inside an integrator). Declared here, below post/, so that the renderer can
// run one; src/post/denoisers.cpp defines make_denoiser, as src/integrators/registry.cpp defines
// make_integrator.
#pragma once
#include <memory>

#include "frame/aov.h"
#include "frame/options.h"
#include "image/image.h"

namespace rl {

class Denoiser {
 public:
  virtual ~Denoiser() = default;
  // Denoises the integrator's raw frame `noisy` into `out` (resized to it) with the same frame's
  // AOVs; called for frames 0, 1, ... of one sequence in order (temporal denoisers keep history).
  virtual void denoise(const Image& noisy, const Aovs& aovs, Image& out) = 0;
  // A-SVGF: true when the denoiser wants the previous frame's samples re-shaded in this frame
  // (Integrator::reshades_previous), given through set_reshaded_previous before denoise.
  virtual bool wants_reshade() const { return false; }
  virtual void set_reshaded_previous(const Image& reshaded) {}
};

// The denoiser o.denoise.method names; null for none. Throws OptionError for one this build lacks.
std::unique_ptr<Denoiser> make_denoiser(const Options& o);

}  // namespace rl
