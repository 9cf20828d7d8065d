// Intel Open Image Denoise (OIDN 2) as the offline reference denoiser, loaded at run time: no build
// dependency. The library is the one denoise.oidn_library names, else $RESTIR_OIDN_LIBRARY, else
// the system's libOpenImageDenoise.so.2 (e.g. the PyPI wheel pyoidn's
// site-packages/pyoidn/oidn/lib/libOpenImageDenoise.so.2, which finds its CPU device beside it).
// Its "RT" filter (HDR) runs on the CPU device over each frame with the AOVs' albedo and normal;
// no history, and OIDN's own threads (render.threads does not bind it).
#pragma once
#include <memory>
#include <string>

#include "frame/denoiser.h"

namespace rl {

class Oidn : public Denoiser {
 public:
  // Loads the library and makes a CPU device; throws OptionError naming the library and why.
  explicit Oidn(const DenoiseOptions& o);
  ~Oidn() override;
  void denoise(const Image& noisy, const Aovs& aovs, Image& out) override;
  // The library path the options and environment choose (what the constructor loads).
  static std::string library_path(const DenoiseOptions& o);

 private:
  struct Api;
  std::unique_ptr<Api> api_;
  void* device_ = nullptr;
};

}  // namespace rl
