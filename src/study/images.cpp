#include "study/images.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <stb_easy_font.h>

#include "image/image_io.h"
#include "image/tonemap.h"
#if __has_include("image/flip.h")
#include "image/flip.h"
#define RESTIR_STUDY_HAS_FLIP 1
#endif

namespace rl::study {

bool flip_available() {
#ifdef RESTIR_STUDY_HAS_FLIP
  return true;
#else
  return false;
#endif
}

double flip_metric(const Image& test, const Image& ref, const OutputOptions& o) {
#ifdef RESTIR_STUDY_HAS_FLIP
  OutputOptions srgb = o;
  srgb.srgb = true;  // FLIP takes sRGB-encoded LDR images
  return mean_flip(tonemap(test, srgb), tonemap(ref, srgb));
#else
  (void)test, (void)ref, (void)o;
  return std::numeric_limits<double>::quiet_NaN();
#endif
}

double flip_metric(const Image& test, const Image& ref, const OutputOptions& o, const std::vector<uint8_t>& mask) {
#ifdef RESTIR_STUDY_HAS_FLIP
  OutputOptions srgb = o;
  srgb.srgb = true;
  const Image map = flip_error_map(tonemap(test, srgb), tonemap(ref, srgb));
  double sum = 0;
  size_t n = 0;
  for (size_t i = 0; i < map.pixels.size() && i < mask.size(); ++i)
    if (mask[i]) sum += double(map.pixels[i].x), ++n;
  return n ? sum / double(n) : std::numeric_limits<double>::quiet_NaN();
#else
  (void)test, (void)ref, (void)o, (void)mask;
  return std::numeric_limits<double>::quiet_NaN();
#endif
}

namespace {
[[maybe_unused]] float luminance(const Rgb& c) { return 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2]; }

Rgb heat(float v) {
  v = std::clamp(std::isfinite(v) ? v : 1.0f, 0.0f, 1.0f);
  // black -> red -> yellow -> white, already display-ready.
  return Rgb(std::min(1.0f, 3 * v), std::clamp(3 * v - 1, 0.0f, 1.0f), std::clamp(3 * v - 2, 0.0f, 1.0f));
}
}  // namespace

Image error_map(const Image& test, const Image& ref, const OutputOptions& o) {
  if (test.width != ref.width || test.height != ref.height) throw std::invalid_argument("error_map: image sizes differ");
  Image out(test.width, test.height);
#ifdef RESTIR_STUDY_HAS_FLIP
  OutputOptions srgb = o;
  srgb.srgb = true;
  Image f = flip_error_map(tonemap(test, srgb), tonemap(ref, srgb));
  for (size_t i = 0; i < f.size(); ++i) out.pixels[i] = heat(f.pixels[i][0]);
#else
  (void)o;
  for (size_t i = 0; i < test.size(); ++i) {
    float r = luminance(ref.pixels[i]);
    out.pixels[i] = heat(std::abs(luminance(test.pixels[i]) - r) / (std::abs(r) + 0.01f));
  }
#endif
  return out;
}

namespace {
// Draws `text` with stb_easy_font (Sean Barrett's public-domain stroke font: it returns quads of
// whole pixels, 4 vertices of 16 bytes each) into an LDR image, top-left corner at (x, y).
void draw_text(Image& img, int x, int y, const std::string& text, Rgb colour) {
  std::string t = text;
  std::vector<char> buffer(270 * (t.size() + 1));  // stb_easy_font's worst case is ~270 bytes per glyph
  const int quads = stb_easy_font_print(0, 0, t.data(), nullptr, buffer.data(), int(buffer.size()));
  for (int q = 0; q < quads; ++q) {
    const float* v0 = reinterpret_cast<const float*>(buffer.data() + size_t(q) * 64);
    const float* v2 = reinterpret_cast<const float*>(buffer.data() + size_t(q) * 64 + 32);
    for (int py = y + int(v0[1]); py < y + int(v2[1]); ++py)
      for (int px = x + int(v0[0]); px < x + int(v2[0]); ++px)
        if (px >= 0 && py >= 0 && px < img.width && py < img.height) img.at(px, py) = colour;
  }
}
}  // namespace

Image error_scale_bar(int width) {
  width = std::max(width, 64);
  constexpr int kBar = 14, kTick = 4, kText = 10, kMargin = 2;
  Image out(width, kBar + kTick + kText + kMargin, Rgb(1));
  const int inner = width - 2 * kMargin;  // room for the first and last labels' halves
  for (int x = 0; x < inner; ++x) {
    const Rgb c = heat(float(x) / float(inner - 1));
    for (int y = 0; y < kBar; ++y) out.at(kMargin + x, y) = c;
  }
  const Rgb ink(0.15f);
  for (int i = 0; i <= 4; ++i) {
    const float v = 0.25f * float(i);
    const int x = kMargin + int(std::lround(v * float(inner - 1)));
    for (int y = kBar; y < kBar + kTick; ++y) out.at(x, y) = ink;
    std::string label = i == 0 ? "0" : i == 4 ? "1" : fmt::format("{:g}", v);
    const int w = stb_easy_font_width(label.data());
    draw_text(out, std::clamp(x - w / 2, 0, width - w), kBar + kTick, label, ink);
  }
  return out;
}

CropRect crop_rect(int width, int height) {
  CropRect r;
  r.width = std::min(width, std::max(8, width / 4));
  r.height = std::min(height, std::max(8, height / 4));
  r.x0 = (width - r.width) / 2;
  r.y0 = (height - r.height) / 2;
  return r;
}

Image zoom_crop(const Image& ldr, int scale) {
  const CropRect r = crop_rect(ldr.width, ldr.height);
  Image out(r.width * scale, r.height * scale);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) out.at(x, y) = ldr.at(r.x0 + x / scale, r.y0 + y / scale);
  return out;
}

double noise_across(const std::vector<Image>& images) {
  if (images.size() < 2) return std::numeric_limits<double>::quiet_NaN();
  const size_t n = images.front().size();
  for (const auto& im : images)
    if (im.size() != n) throw std::invalid_argument("noise_across: image sizes differ");
  double total = 0;
  const double k = double(images.size());
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      double s = 0, ss = 0;
      for (const auto& im : images) {
        double v = im.pixels[i][c];
        s += v;
        ss += v * v;
      }
      double mean = s / k;
      total += std::sqrt(std::max(0.0, (ss - k * mean * mean) / (k - 1)));
    }
  return total / (3.0 * double(n));
}

void write_config_images(const std::string& prefix, const Image& img, const Image* ref, const OutputOptions& o, bool exr) {
  if (exr) write_exr(prefix + ".exr", img);
  Image ldr = tonemap(img, o);
  write_png(prefix + ".png", ldr);
  write_png(prefix + "-crop.png", zoom_crop(ldr));
  if (ref) {
    Image e = error_map(img, *ref, o);
    write_png(prefix + "-error.png", e);
    write_png(prefix + "-error-crop.png", zoom_crop(e));
  }
}

}  // namespace rl::study
