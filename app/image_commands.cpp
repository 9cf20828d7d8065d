// `restir compare` (error metrics of a test image against a reference: MSE, relMSE, MAE, FLIP; an
// error map; a crop) and `restir tonemap` (an EXR to a display-ready PNG).
#include <fmt/format.h>

#include <cctype>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>

#include "cli.h"
#include "core/io_error.h"
#include "core/option_io.h"
#include "core/output_guard.h"
#include "frame/options.h"
#include "image/image_io.h"
#include "image/metrics.h"
#include "image/tonemap.h"
#include "study/images.h"

namespace rl::cli {

namespace fs = std::filesystem;

namespace {

// Display-referred (tone-mapped, sRGB 8-bit) files against scene-linear ones give meaningless metrics.
bool display_referred(const std::string& path) {
  std::string e = fs::path(path).extension().string();
  for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
  return e == ".png" || e == ".jpg" || e == ".jpeg" || e == ".bmp" || e == ".tga";
}

// The configuration restir wrote into an EXR's header (restir.config), if any.
std::optional<Options> recorded_options(const std::string& path) {
  if (display_referred(path)) return std::nullopt;
  for (const auto& [k, v] : read_exr_metadata(path)) {
    if (k != "restir.config") continue;
    try {
      Options o;
      apply_options_json(o, v);
      return o;
    } catch (const std::exception&) {
      return std::nullopt;  // written by another version: no claim about what it estimates
    }
  }
  return std::nullopt;
}

// What an image estimates, in words, as far as its configuration decides it: the path depth (ReSTIR
// DI and SSR estimate less than a path tracer of the same scene) and the resolution.
std::string estimand(const Options& o) {
  std::string what;
  if (o.integrator == "restir-di") what = "direct light only (restir-di: paths of 1 bounce)";
  else if (o.integrator == "ssr") what = "screen-space reflections (ssr: reflections traced in screen space, biased)";
  // pt, restir-gi and restir-pt estimate the same integral at the same depth: no integrator name.
  else what = fmt::format("paths of up to {} bounces", o.path.max_depth);
  // Not the frame: a static scene's integral is the same at every frame of a sequence.
  return fmt::format("{} at {}x{}", what, o.film.width, o.film.height);
}

// A warning when the two images' recorded configurations estimate different integrals: the
// metrics then measure that difference, not noise or bias.
void warn_if_different_integrals(const CompareArgs& a, const std::optional<Options>& t, const std::optional<Options>& r) {
  if (!t || !r) return;
  const std::string et = estimand(*t), er = estimand(*r);
  if (et != er)
    std::fprintf(stderr, "warning: compare: the images estimate different integrals: '%s' renders %s, '%s' renders %s; "
                 "the metrics measure that difference, not only error\n", a.test.c_str(), et.c_str(), a.reference.c_str(), er.c_str());
}

// --crop X,Y,W,H: the region, checked against the image.
Image crop(const Image& img, const std::string& spec, const char* which) {
  int x = 0, y = 0, w = 0, h = 0;
  char end = 0;
  if (std::sscanf(spec.c_str(), "%d,%d,%d,%d%c", &x, &y, &w, &h, &end) != 4 || w <= 0 || h <= 0 || x < 0 || y < 0)
    throw UsageError(fmt::format("compare: --crop '{}': expected X,Y,W,H (pixels, W and H > 0)", spec));
  if (x + w > img.width || y + h > img.height)
    throw OptionError(fmt::format("compare: --crop {},{},{},{} lies outside the {} image ({}x{})", x, y, w, h, which, img.width, img.height));
  Image out(w, h);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) out.at(i, j) = img.at(x + i, y + j);
  return out;
}

// The error map above its colour scale, one PNG.
Image error_map_with_scale(const Image& test, const Image& ref, const OutputOptions& o) {
  const Image map = study::error_map(test, ref, o);
  const Image bar = study::error_scale_bar(std::max(map.width, 64));
  Image out(std::max(map.width, bar.width), map.height + bar.height, Rgb(1));
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) out.at(x, y) = map.at(x, y);
  for (int y = 0; y < bar.height; ++y)
    for (int x = 0; x < bar.width; ++x) out.at(x, map.height + y) = bar.at(x, y);
  return out;
}

}  // namespace

int run_compare(const CompareArgs& a) {
  if (display_referred(a.test) != display_referred(a.reference))
    throw OptionError(fmt::format("compare: '{}' is {} but '{}' is {}: the metrics would be meaningless; compare "
                                  "two linear images (EXR) or two tone-mapped ones", a.test,
                                  display_referred(a.test) ? "tone-mapped (8-bit sRGB)" : "linear HDR", a.reference,
                                  display_referred(a.reference) ? "tone-mapped (8-bit sRGB)" : "linear HDR"));
  if (!a.error_map.empty()) check_outputs({{a.error_map, "--error-map", {".png"}}}, {a.test, a.reference});
  Image test = read_image(a.test), ref = read_image(a.reference);
  if (test.width != ref.width || test.height != ref.height)
    throw OptionError(fmt::format("compare: '{}' is {}x{} but '{}' is {}x{}", a.test, test.width, test.height, a.reference,
                                  ref.width, ref.height));
  if (!a.crop.empty()) test = crop(test, a.crop, "test"), ref = crop(ref, a.crop, "reference");
  const std::optional<Options> test_options = recorded_options(a.test);
  warn_if_different_integrals(a, test_options, recorded_options(a.reference));
  // FLIP compares what a viewer sees: the tone mapping the test image was rendered with (as a study
  // does), or, for tone-mapped files, the images themselves (linear tone mapping, exposure 0, undoes
  // the sRGB decoding read_image applied).
  OutputOptions display = test_options.value_or(Options{}).output;
  if (display_referred(a.test)) display = OutputOptions{Tonemap::linear, 0, 1, true};
  const double m = mse(test, ref), r = rel_mse(test, ref), e = mean_abs_error(test, ref);
  const double f = study::flip_metric(test, ref, display);
  const double lt = image_stats(test).mean_luminance, lr = image_stats(ref).mean_luminance;
  if (!a.error_map.empty()) write_png(a.error_map, error_map_with_scale(test, ref, display));
  if (a.json) {
    fmt::print("{{\"mse\": {:.9g}, \"relmse\": {:.9g}, \"mae\": {:.9g}, \"flip\": {:.9g}, \"mean_luminance_test\": {:.9g}, "
               "\"mean_luminance_reference\": {:.9g}}}\n", m, r, e, f, lt, lr);
  } else {
    fmt::print("MSE     {:.6g}\nrelMSE  {:.6g}\nMAE     {:.6g}\nFLIP    {:.6g}  (LDR-FLIP after {} tone mapping)\n"
               "mean luminance  test {:.6g}  reference {:.6g}\n", m, r, e, f, enum_name(display.tonemap), lt, lr);
    if (!a.error_map.empty()) fmt::print("error map (FLIP, black 0 to white 1): {}\n", a.error_map);
  }
  return 0;
}

int run_tonemap(const TonemapArgs& a) {
  check_outputs({{a.out, "OUT", {".png"}}}, {a.in});
  Image hdr = read_image(a.in);
  // The tone mapping the image was rendered with, unless overridden.
  Options o = recorded_options(a.in).value_or(Options{});
  for (const std::string& s : a.sets) {
    if (!s.starts_with("output.")) throw UsageError(fmt::format("tonemap: --set {}: only output.* options apply to an image", s));
    set_option_assignment(o, s);
  }
  write_png(a.out, tonemap(hdr, o.output));
  return 0;
}

}  // namespace rl::cli
