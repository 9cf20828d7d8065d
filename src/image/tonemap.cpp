// Tone mapping operators and the sRGB transfer curve. Formulas and sources are cited at each one.
#include "image/tonemap.h"

#include <cmath>
#include <stdexcept>

namespace rl {

namespace {

// Largest value a channel is allowed to take before the operator: keeps +inf and huge values
// finite so the luminance ratio below is well defined (operators are evaluated in double).
constexpr double kChannelMax = 1e30;

double sanitize(float v) {
  if (std::isnan(v)) return 0.0;
  return std::clamp(double(v), 0.0, kChannelMax);
}

// Reinhard, Stark, Shirley, Ferwerda 2002, "Photographic Tone Reproduction for Digital Images",
// eq. 3: L_d = L / (1 + L).  (Their eq. 2 key-value scaling a / L̄_w is replaced by the user's
// exposure; we do not compute a log-average luminance.)
double reinhard_curve(double l) { return l / (1.0 + l); }

// Same paper, eq. 4: L_d = L (1 + L / L_white^2) / (1 + L); L = L_white maps to exactly 1 and
// larger values burn out (clamped afterwards).
double modified_reinhard_curve(double l, double l_white) {
  return l * (1.0 + l / (l_white * l_white)) / (1.0 + l);
}

// ACES filmic: Krzysztof Narkowicz 2015, "ACES Filmic Tone Mapping Curve" (blog post,
// knarkowicz.wordpress.com), a rational fit of the ACES RRT+ODT:
//   f(x) = x (a x + b) / (x (c x + d) + e),  a = 2.51, b = 0.03, c = 2.43, d = 0.59, e = 0.14.
// f(0) = 0, f is increasing on x >= 0 and reaches 1 at x ≈ 7.24 (its asymptote a/c ≈ 1.033 is
// cut by the clamp to [0,1]). Applied per channel, as in the post. We apply the curve to the
// exposed value directly (no extra 0.6 pre-scale), so exposure keeps its photographic meaning.
double aces_narkowicz(double x) {
  constexpr double a = 2.51, b = 0.03, c = 2.43, d = 0.59, e = 0.14;
  return x * (a * x + b) / (x * (c * x + d) + e);
}

float to_unit(double v) { return float(std::clamp(v, 0.0, 1.0)); }

}  // namespace

float srgb_encode(float linear) {
  // IEC 61966-2-1: linear segment below the knee 0.0031308, power 1/2.4 above it.
  if (linear <= 0.0031308f) return 12.92f * linear;
  return 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

float srgb_decode(float encoded) {
  // Inverse of srgb_encode; the knee in encoded space is 12.92 * 0.0031308 ≈ 0.04045.
  if (encoded <= 0.04045f) return encoded / 12.92f;
  return std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

Rgb tonemap_pixel(Rgb linear, const OutputOptions& o) {
  const float scale = std::exp2(o.exposure);  // exposure in stops: 2^stops
  double c[3];
  for (int i = 0; i < 3; ++i) c[i] = sanitize(linear[i] * scale);

  double out[3] = {c[0], c[1], c[2]};
  switch (o.tonemap) {
    case Tonemap::linear:
      break;  // identity; the clamp below does the work
    case Tonemap::reinhard:
    case Tonemap::modified_reinhard: {
      // Luminance with Rec. 709 weights (same as rl::luminance), in double: c can be up to 1e30.
      double l = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
      if (l <= 0) {
        out[0] = out[1] = out[2] = 0;  // channels are >= 0 with positive weights: all are 0
        break;
      }
      double ld = o.tonemap == Tonemap::reinhard ? reinhard_curve(l)
                                                 : modified_reinhard_curve(l, double(o.white_point));
      double ratio = ld / l;  // colour scaled by L_d / L: chromaticity kept
      for (int i = 0; i < 3; ++i) out[i] = c[i] * ratio;
      break;
    }
    case Tonemap::aces:
      for (int i = 0; i < 3; ++i) out[i] = aces_narkowicz(c[i]);
      break;
  }

  Rgb r(to_unit(out[0]), to_unit(out[1]), to_unit(out[2]));
  if (o.srgb) r = Rgb(srgb_encode(r.x), srgb_encode(r.y), srgb_encode(r.z));
  return r;
}

Image tonemap(const Image& hdr, const OutputOptions& o) {
  if (hdr.width < 0 || hdr.height < 0 || hdr.pixels.size() != size_t(hdr.width) * size_t(hdr.height))
    throw std::invalid_argument("tonemap: image pixel count does not match its width x height");
  Image out(hdr.width, hdr.height);
  for (size_t i = 0; i < hdr.pixels.size(); ++i) out.pixels[i] = tonemap_pixel(hdr.pixels[i], o);
  return out;
}

}  // namespace rl
