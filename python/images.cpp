// Images between numpy and the library: EXR/PNG I/O, tone mapping, and the metrics a study
// computes (MSE, relMSE, MAE, FLIP), each a call into src/image or src/study.
#include <nanobind/stl/map.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>
#include <nanobind/stl/pair.h>

#include <cstring>
#include <map>

#include "bindings.h"
#include "frame/options.h"
#include "image/image_io.h"
#include "image/metrics.h"
#include "image/tonemap.h"
#include "study/images.h"

namespace rl::py {

ImageArray image_view(Image& img, nb::handle owner) {
  return ImageArray(img.pixels.data(), {size_t(img.height), size_t(img.width), 3}, owner);
}

ImageArray image_array(Image&& img) {
  auto* held = new Image(std::move(img));
  nb::capsule owner(held, [](void* p) noexcept { delete static_cast<Image*>(p); });
  return image_view(*held, owner);
}

Image to_image(const ImageInput& a) {
  Image img(int(a.shape(1)), int(a.shape(0)));
  std::memcpy(static_cast<void*>(img.pixels.data()), a.data(), img.size() * sizeof(Rgb));
  return img;
}

namespace {

// The tone mapping of output.* option values (a dict as for Renderer), checked as --set checks them.
OutputOptions output_options(nb::handle options) {
  Options o;
  for (const auto& [k, v] : option_assignments(options)) {
    if (!k.starts_with("output.")) throw OptionError("option '" + k + "': only output.* options apply to an image");
    set_option(o, k, v);
  }
  return o.output;
}

void bind_metrics(nb::module_& m) {
  // The images are copied under the GIL, then compared without it.
  m.def("mse", [](const ImageInput& t, const ImageInput& r) {
        const Image a = to_image(t), b = to_image(r);
        nb::gil_scoped_release unlocked;
        return mse(a, b);
      }, nb::arg("test"), nb::arg("reference"), "Mean squared error over pixels and channels.");
  m.def("relmse", [](const ImageInput& t, const ImageInput& r, double eps) {
        const Image a = to_image(t), b = to_image(r);
        nb::gil_scoped_release unlocked;
        return rel_mse(a, b, eps);
      }, nb::arg("test"), nb::arg("reference"), nb::arg("eps") = 0.01,
      "Relative MSE as pbrt-v4 computes it: mean of (t - r)^2 / (r + eps)^2.");
  m.def("mae", [](const ImageInput& t, const ImageInput& r) {
        const Image a = to_image(t), b = to_image(r);
        nb::gil_scoped_release unlocked;
        return mean_abs_error(a, b);
      }, nb::arg("test"), nb::arg("reference"), "Mean absolute error.");
  m.def("flip", [](const ImageInput& t, const ImageInput& r, std::optional<nb::dict> options) {
        const Image a = to_image(t), b = to_image(r);
        const OutputOptions o = output_options(dict_or_none(options));
        nb::gil_scoped_release unlocked;
        return study::flip_metric(a, b, o);
      }, nb::arg("test"), nb::arg("reference"), nb::arg("options") = nb::none(),
      "Mean LDR-FLIP of two linear images after the tone mapping of output.* options (a study's metric, "
      "`restir compare`'s FLIP).");
}

}  // namespace

void bind_images(nb::module_& m) {
  m.def("read_image", [](const std::string& path) { return image_array(read_image(path)); }, nb::arg("path"),
        "Reads an EXR, PNG or HDR file as H x W x 3 float32 linear RGB (the CLI's reader).");
  m.def("read_exr_metadata", [](const std::string& path) {
        std::map<std::string, std::string> d;
        for (auto& [k, v] : read_exr_metadata(path)) d[k] = v;
        return d;
      }, nb::arg("path"), "The string attributes of an EXR header (restir.config: the options it was rendered with).");
  m.def("write_exr", [](const std::string& path, const ImageInput& img, const std::map<std::string, std::string>& meta) {
        write_exr(path, to_image(img), {meta.begin(), meta.end()});
      }, nb::arg("path"), nb::arg("image"), nb::arg("metadata") = std::map<std::string, std::string>{},
      "Writes a float32 EXR atomically, with string attributes in its header.");
  m.def("tonemap", [](const ImageInput& img, std::optional<nb::dict> options) { return image_array(tonemap(to_image(img), output_options(dict_or_none(options)))); },
        nb::arg("image"), nb::arg("options") = nb::none(),
        "The display image (values in [0, 1], sRGB-encoded unless output.srgb is false) of output.* options.");
  m.def("write_png", [](const std::string& path, const ImageInput& img, std::optional<nb::dict> options) {
        write_png(path, tonemap(to_image(img), output_options(dict_or_none(options))));
      }, nb::arg("path"), nb::arg("image"), nb::arg("options") = nb::none(),
      "Tone maps a linear image (output.* options) and writes an 8-bit PNG, as --png does.");
  bind_metrics(m);
}

}  // namespace rl::py
