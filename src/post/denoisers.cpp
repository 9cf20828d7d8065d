// The post-process stage's one switch (frame/denoiser.h): denoise.method -> a Denoiser, and for
// SVGF and A-SVGF the SVGF of the backend render.backend names.
#include <stdexcept>
#include <string>

#include "backends/cuda/cuda_queries.h"
#include "frame/denoiser.h"
#include "post/asvgf.h"
#include "post/oidn.h"
#include "post/svgf.h"
#include "post/svgf_driver.h"

namespace rl {

namespace {

// cpu: the vectorised Svgf (the fast one); cpu-bvh and cuda: the per-pixel stages the BVH
// backends share (svgf_driver.h, the same floats), on the host or on the device.
std::unique_ptr<SvgfFilter> make_svgf(const Options& o) {
  switch (o.render.backend) {
    case Backend::cpu:
      return std::make_unique<Svgf>(o.denoise);
    case Backend::cpu_bvh:
      return std::make_unique<SvgfStages<HostExec>>(o.denoise);
    case Backend::cuda:
#ifdef RESTIR_HAVE_CUDA
      try {
        return make_svgf_cuda(o.denoise);
      } catch (const std::runtime_error& e) {  // the device (BackendError) or the CUDA runtime
        throw OptionError(std::string("render.backend = cuda: ") + e.what());
      }
#else
      throw OptionError("render.backend = cuda: " + cuda_unavailable_reason());
#endif
  }
  return nullptr;
}

}  // namespace

std::unique_ptr<Denoiser> make_denoiser(const Options& o) {
  switch (o.denoise.method) {
    case DenoiseMethod::none:
      return nullptr;
    case DenoiseMethod::svgf:
      return make_svgf(o);
    case DenoiseMethod::asvgf:
      return std::make_unique<Asvgf>(o.denoise, make_svgf(o));
    case DenoiseMethod::oidn:
      return std::make_unique<Oidn>(o.denoise);
  }
  return nullptr;
}

}  // namespace rl
