#include "post/oidn.h"

#include <dlfcn.h>
#include <fmt/format.h>

#include <cstdlib>
#include <vector>

#include "core/option_io.h"

namespace rl {

// The few functions of OIDN 2's C API used here (include/OpenImageDenoise/oidn.h), declared
// ourselves so that nothing of OIDN is needed to build. Handles are opaque pointers; the enums
// are ints: OIDN_DEVICE_TYPE_CPU = 1, OIDN_FORMAT_FLOAT3 = 3, OIDN_ERROR_NONE = 0.
struct Oidn::Api {
  void* lib = nullptr;
  void* (*new_device)(int type) = nullptr;
  void (*commit_device)(void* device) = nullptr;
  int (*get_device_error)(void* device, const char** message) = nullptr;
  void (*release_device)(void* device) = nullptr;
  void* (*new_filter)(void* device, const char* type) = nullptr;
  void (*set_shared_filter_image)(void* filter, const char* name, void* ptr, int format, size_t width, size_t height,
                                  size_t byte_offset, size_t pixel_byte_stride, size_t row_byte_stride) = nullptr;
  void (*set_filter_bool)(void* filter, const char* name, bool value) = nullptr;
  void (*commit_filter)(void* filter) = nullptr;
  void (*execute_filter)(void* filter) = nullptr;
  void (*release_filter)(void* filter) = nullptr;
};

namespace {
constexpr int kDeviceCpu = 1, kFormatFloat3 = 3, kErrorNone = 0;

template <class F>
void bind(void* lib, const std::string& path, const char* name, F& f) {
  f = reinterpret_cast<F>(dlsym(lib, name));
  if (!f) throw OptionError(fmt::format("denoise.method = oidn: '{}' has no {} (not OIDN 2?)", path, name));
}
}  // namespace

std::string Oidn::library_path(const DenoiseOptions& o) {
  if (!o.oidn_library.empty()) return o.oidn_library;
  if (const char* env = std::getenv("RESTIR_OIDN_LIBRARY"); env && *env) return env;
  return "libOpenImageDenoise.so.2";
}

Oidn::Oidn(const DenoiseOptions& o) : api_(std::make_unique<Api>()) {
  const std::string path = library_path(o);
  // Never closed: OIDN's worker threads may outlive a dlclose.
  api_->lib = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!api_->lib)
    throw OptionError(fmt::format("denoise.method = oidn: cannot load '{}' ({}); set denoise.oidn_library or "
                                  "RESTIR_OIDN_LIBRARY to an OIDN 2 libOpenImageDenoise.so (pip install pyoidn: "
                                  "pyoidn/oidn/lib/libOpenImageDenoise.so.2)", path, dlerror()));
  Api& a = *api_;
  bind(a.lib, path, "oidnNewDevice", a.new_device);
  bind(a.lib, path, "oidnCommitDevice", a.commit_device);
  bind(a.lib, path, "oidnGetDeviceError", a.get_device_error);
  bind(a.lib, path, "oidnReleaseDevice", a.release_device);
  bind(a.lib, path, "oidnNewFilter", a.new_filter);
  bind(a.lib, path, "oidnSetSharedFilterImage", a.set_shared_filter_image);
  bind(a.lib, path, "oidnSetFilterBool", a.set_filter_bool);
  bind(a.lib, path, "oidnCommitFilter", a.commit_filter);
  bind(a.lib, path, "oidnExecuteFilter", a.execute_filter);
  bind(a.lib, path, "oidnReleaseFilter", a.release_filter);
  device_ = a.new_device(kDeviceCpu);
  if (device_) a.commit_device(device_);
  const char* why = nullptr;
  if (!device_ || a.get_device_error(device_, &why) != kErrorNone)
    throw OptionError(fmt::format("denoise.method = oidn: '{}' made no CPU device: {}", path, why ? why : "unknown error"));
}

Oidn::~Oidn() {
  if (device_) api_->release_device(device_);
}

void Oidn::denoise(const Image& noisy, const Aovs& aovs, Image& out) {
  const Api& a = *api_;
  out = Image(noisy.width, noisy.height);
  std::vector<Rgb> albedo = aovs.albedo, normal(aovs.normal.begin(), aovs.normal.end());
  // Where no surface was hit OIDN wants the environment's colour as albedo and a zero normal.
  for (size_t i = 0; i < albedo.size(); ++i)
    if (!aovs.valid(i)) albedo[i] = Rgb(0);
  void* filter = a.new_filter(device_, "RT");
  const size_t w = size_t(noisy.width), h = size_t(noisy.height);
  a.set_shared_filter_image(filter, "color", const_cast<Rgb*>(noisy.pixels.data()), kFormatFloat3, w, h, 0, 0, 0);
  a.set_shared_filter_image(filter, "albedo", albedo.data(), kFormatFloat3, w, h, 0, 0, 0);
  a.set_shared_filter_image(filter, "normal", normal.data(), kFormatFloat3, w, h, 0, 0, 0);
  a.set_shared_filter_image(filter, "output", out.pixels.data(), kFormatFloat3, w, h, 0, 0, 0);
  a.set_filter_bool(filter, "hdr", true);
  a.commit_filter(filter);
  a.execute_filter(filter);
  const char* why = nullptr;
  const int err = a.get_device_error(device_, &why);
  a.release_filter(filter);
  if (err != kErrorNone) throw std::runtime_error(fmt::format("oidn: the RT filter failed: {}", why ? why : "unknown error"));
}

}  // namespace rl
