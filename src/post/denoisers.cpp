// The post-process stage's one switch (frame/denoiser.h): denoise.method -> a Denoiser.
#include "frame/denoiser.h"
#include "post/asvgf.h"
#include "post/oidn.h"
#include "post/svgf.h"

namespace rl {

std::unique_ptr<Denoiser> make_denoiser(const Options& o) {
  switch (o.denoise.method) {
    case DenoiseMethod::none:
      return nullptr;
    case DenoiseMethod::svgf:
      return std::make_unique<Svgf>(o.denoise);
    case DenoiseMethod::asvgf:
      return std::make_unique<Asvgf>(o.denoise);
    case DenoiseMethod::oidn:
      return std::make_unique<Oidn>(o.denoise);
  }
  return nullptr;
}

}  // namespace rl
