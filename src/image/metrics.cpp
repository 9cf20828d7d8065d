// Error metrics and pixel statistics; conventions and citations in metrics.h.
#include "image/metrics.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

namespace rl {

namespace {

void check_shape(const Image& img, const char* fn, const char* which) {
  if (img.width < 0 || img.height < 0 || img.pixels.size() != size_t(img.width) * size_t(img.height))
    throw std::invalid_argument(fmt::format("{}: {} image has {} pixels but is {}x{}", fn, which,
                                            img.pixels.size(), img.width, img.height));
}

void check_finite(const Image& img, const char* fn, const char* which) {
  for (size_t i = 0; i < img.pixels.size(); ++i) {
    if (!is_finite(img.pixels[i])) {
      const Rgb& p = img.pixels[i];
      throw std::invalid_argument(fmt::format("{}: {} image has a non-finite pixel at (x={}, y={}): ({}, {}, {})",
                                              fn, which, i % size_t(img.width), i / size_t(img.width), p.x, p.y, p.z));
    }
  }
}

// Validates a (test, reference) pair the same way for every metric.
void check_pair(const Image& test, const Image& ref, const char* fn) {
  check_shape(test, fn, "test");
  check_shape(ref, fn, "reference");
  if (test.width != ref.width || test.height != ref.height)
    throw std::invalid_argument(fmt::format("{}: size mismatch: test is {}x{}, reference is {}x{}", fn, test.width,
                                            test.height, ref.width, ref.height));
  if (test.empty()) throw std::invalid_argument(fmt::format("{}: images are empty (0x0)", fn));
  check_finite(test, fn, "test");
  check_finite(ref, fn, "reference");
}

// (1/N) Σ over pixels and channels of term(t, r), N = 3 * pixels.
template <class F>
double channel_mean(const Image& test, const Image& ref, F term, const std::vector<uint8_t>* mask = nullptr) {
  double sum = 0;
  size_t n = 0;
  for (size_t i = 0; i < test.pixels.size(); ++i) {
    if (mask && !(*mask)[i]) continue;
    for (int c = 0; c < 3; ++c) sum += term(double(test.pixels[i][c]), double(ref.pixels[i][c]));
    ++n;
  }
  return n ? sum / (3.0 * double(n)) : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

double mse(const Image& test, const Image& ref) {
  check_pair(test, ref, "mse");
  return channel_mean(test, ref, [](double t, double r) { return (t - r) * (t - r); });
}

double rel_mse(const Image& test, const Image& ref, double eps) { return rel_mse(test, ref, nullptr, eps); }

double rel_mse(const Image& test, const Image& ref, const std::vector<uint8_t>* mask, double eps) {
  check_pair(test, ref, "rel_mse");
  if (!(eps >= 0) || !std::isfinite(eps))
    throw std::invalid_argument(fmt::format("rel_mse: eps must be finite and >= 0, got {}", eps));
  if (mask && mask->size() != test.pixels.size())
    throw std::invalid_argument(fmt::format("rel_mse: mask of {} pixels for {} pixels", mask->size(), test.pixels.size()));
  // pbrt-v4 Image::MRSE: rse = Sqr(v - vref) / Sqr(vref + 0.01); infinite terms skipped.
  return channel_mean(test, ref, [eps](double t, double r) {
    double d = t - r, den = (r + eps) * (r + eps);
    if (d == 0) return 0.0;
    if (den == 0) return 0.0;  // infinite term: skipped as in pbrt (still counted in N)
    double rse = d * d / den;
    return std::isinf(rse) ? 0.0 : rse;
  }, mask);
}

namespace {
// The mean of img over block x block tiles (partial tiles at the right and bottom edges).
Image block_means(const Image& img, int block) {
  Image out((img.width + block - 1) / block, (img.height + block - 1) / block);
  std::vector<double> sum(out.pixels.size() * 3, 0.0);
  std::vector<int> count(out.pixels.size(), 0);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const size_t t = size_t(y / block) * size_t(out.width) + size_t(x / block);
      const Rgb& p = img.pixels[size_t(y) * size_t(img.width) + size_t(x)];
      for (int c = 0; c < 3; ++c) sum[3 * t + c] += double(p[c]);
      ++count[t];
    }
  for (size_t t = 0; t < out.pixels.size(); ++t)
    for (int c = 0; c < 3; ++c) out.pixels[t][c] = float(sum[3 * t + c] / double(count[t]));
  return out;
}
}  // namespace

double rel_mse_lowpass(const Image& test, const Image& ref, int block, double eps) {
  check_pair(test, ref, "rel_mse_lowpass");
  if (block < 1) throw std::invalid_argument(fmt::format("rel_mse_lowpass: block must be >= 1, got {}", block));
  return rel_mse(block_means(test, block), block_means(ref, block), eps);
}

double mean_abs_error(const Image& test, const Image& ref) {
  check_pair(test, ref, "mean_abs_error");
  return channel_mean(test, ref, [](double t, double r) { return std::fabs(t - r); });
}

ImageStats image_stats(const Image& img) {
  check_shape(img, "image_stats", "input");
  ImageStats s;
  double sum = 0;
  size_t finite = 0;
  for (const Rgb& p : img.pixels) {
    if (std::isnan(p.x) || std::isnan(p.y) || std::isnan(p.z)) {
      ++s.nan_count;
    } else if (std::isinf(p.x) || std::isinf(p.y) || std::isinf(p.z)) {
      ++s.inf_count;
    } else {
      if (p.x < 0 || p.y < 0 || p.z < 0) ++s.negative_count;
      sum += 0.2126 * p.x + 0.7152 * p.y + 0.0722 * p.z;  // Rec. 709 luminance, as rl::luminance
      ++finite;
    }
  }
  s.mean_luminance = finite ? sum / double(finite) : 0.0;
  return s;
}

}  // namespace rl
