// LDR-FLIP (Andersson et al. 2020, "FLIP: A Difference Evaluator for Alternating Images").
//
// Pipeline, in the order of the paper (colour pipeline, feature pipeline, final error). The steps
// are numbered here and the code refers to these numbers:
//   0. sRGB -> linear RGB -> CIE XYZ -> YCxCz, the linearised opponent space of S-CIELAB
//      (Zhang & Wandell 1997): Y = 116 y/yn - 16, Cx = 500 (x/xn - y/yn), Cz = 200 (y/yn - z/zn).
//   Colour pipeline
//   1. Spatial filtering with the contrast sensitivity function of each opponent channel, modelled
//      in the spatial domain as a sum of Gaussians
//        s(x) = a1 sqrt(pi/b1) exp(-pi^2 x^2 / b1) + a2 sqrt(pi/b2) exp(-pi^2 x^2 / b2),
//      x in degrees of visual angle (x = pixel offset / ppd), weights normalised to sum 1.
//      Parameters (a1, b1, a2, b2): achromatic (1, 0.0047, 0, 1e-5), red-green (1, 0.0053, 0, 1e-5),
//      blue-yellow (34.1, 0.04, 13.5, 0.025).
//   2. Back to linear RGB, clamped to [0,1] (the filtered colour must be displayable), then to
//      CIELAB, then the Hunt adjustment a_h = 0.01 L a, b_h = 0.01 L b (chroma shrinks with
//      lightness, as the Hunt effect predicts).
//   3. HyAB distance (Abasi et al. 2020): |dL| + sqrt(da^2 + db^2), raised to qc = 0.7.
//   4. Remapping to [0,1]: with cmax = HyAB(green, blue)^qc (the largest distance between two
//      colours of the RGB cube in this space) and the knee pc * cmax, pc = 0.4, the range
//      [0, pc cmax) maps linearly onto [0, pt), pt = 0.95, and [pc cmax, cmax] onto [pt, 1]:
//      most of [0,1] goes to small and moderate differences, which are the ones to tell apart.
//   Feature pipeline (on the achromatic channel only, normalised to [0,1]: (Y + 16) / 116, per the
//   paper's erratum for p. 10, "division by 116")
//   5. Edges: the gradient magnitude with first-derivative-of-Gaussian filters; points: the
//      magnitude of the pair of second-derivative-of-Gaussian filters (x and y). The Gaussian has
//      sigma = 0.5 w ppd pixels, w = 0.082 degrees (peak-to-trough width of the human edge
//      detector); radius ceil(3 sigma). Positive weights of each derivative filter are normalised
//      to sum 1 and negative weights to sum -1, the Gaussian to sum 1.
//   6. Feature difference: dE_f = ( max(| |e_ref| - |e_test| |, | |p_ref| - |p_test| |) / sqrt(2) )^qf,
//      qf = 0.5.
//   Final error
//   7. dE = dE_c ^ (1 - dE_f): feature differences amplify the colour difference (exponent < 1).
//
// Implementation notes
//  - Every filter is separable and is applied as two 1-D passes with clamp-to-edge borders. The
//    blue-yellow CSF is a sum of two Gaussians, so it is two separable filters whose results are
//    added; the 1-D weights of both carry sqrt(a sqrt(pi/b)) and a common factor chosen so that the
//    2-D kernel sums to 1 exactly as the paper's 2-D kernel does. Each 2-D derivative filter is
//    (derivative in x) x (Gaussian in y), whose positive/negative 2-D sums factor the same way, so
//    the 1-D normalisation above equals the paper's 2-D one.
//  - The CSF kernel is evaluated on the square [-r, r]^2 with one radius for all channels,
//    r = ceil(3 sqrt(b_max / (2 pi^2)) ppd), b_max = 0.04 the widest Gaussian (3 standard
//    deviations of it); r = 10 pixels at 67 ppd. This radius is the reference implementation's.
//  - All arithmetic is in double (the reference code uses float); the map is returned as float.
#include "image/flip.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/parallel.h"

namespace rl {
namespace {

constexpr double kPiD = 3.14159265358979323846;

// FLIP constants (paper: qc, pc, pt of the colour pipeline; w, qf of the feature pipeline).
constexpr double kQc = 0.7;   // colour difference exponent
constexpr double kPc = 0.4;   // knee of the colour remapping, as a fraction of cmax
constexpr double kPt = 0.95;  // remapped value at the knee
constexpr double kW = 0.082;  // width (degrees) of the edge detector, peak to trough = 2 sigma
constexpr double kQf = 0.5;   // feature difference exponent

// CSF parameters (a1, b1, a2, b2) per opponent channel.
struct CsfParams {
  double a1, b1, a2, b2;
};
constexpr CsfParams kCsfA{1.0, 0.0047, 0.0, 1e-5};
constexpr CsfParams kCsfRG{1.0, 0.0053, 0.0, 1e-5};
constexpr CsfParams kCsfBY{34.1, 0.04, 13.5, 0.025};
constexpr double kCsfMaxB = 0.04;

using D3 = std::array<double, 3>;
using M3 = std::array<D3, 3>;

// Linear sRGB (Rec. 709 primaries, D65) -> XYZ, in the exact rational form of the reference code.
constexpr M3 kRgbToXyz{{{10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0},
                        {2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0},
                        {1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0}}};

D3 mul(const M3& m, const D3& v) {
  return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2], m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
          m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}

M3 inverse(const M3& m) {
  const double c00 = m[1][1] * m[2][2] - m[1][2] * m[2][1];
  const double c01 = m[1][2] * m[2][0] - m[1][0] * m[2][2];
  const double c02 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
  const double inv_det = 1.0 / (m[0][0] * c00 + m[0][1] * c01 + m[0][2] * c02);
  M3 r;
  r[0] = {c00 * inv_det, (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * inv_det,
          (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * inv_det};
  r[1] = {c01 * inv_det, (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * inv_det,
          (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * inv_det};
  r[2] = {c02 * inv_det, (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * inv_det,
          (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * inv_det};
  return r;
}

// The colour-space constants, computed once.
struct ColorSpace {
  M3 xyz_to_rgb = inverse(kRgbToXyz);
  D3 white = mul(kRgbToXyz, {1.0, 1.0, 1.0});  // reference illuminant: XYZ of RGB white (D65, Y = 1)
};
const ColorSpace& color_space() {
  static const ColorSpace cs;
  return cs;
}

double srgb_to_linear(double e) {
  return e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4);
}

// XYZ -> YCxCz (linear in XYZ, so filtering there commutes with the conversion back).
D3 xyz_to_ycxcz(const D3& xyz) {
  const D3& w = color_space().white;
  const double x = xyz[0] / w[0], y = xyz[1] / w[1], z = xyz[2] / w[2];
  return {116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)};
}

D3 ycxcz_to_xyz(const D3& c) {
  const D3& w = color_space().white;
  const double y = (c[0] + 16.0) / 116.0;
  return {(y + c[1] / 500.0) * w[0], y * w[1], (y - c[2] / 200.0) * w[2]};
}

// CIE 1976 L*a*b* relative to the same white.
D3 xyz_to_lab(const D3& xyz) {
  const D3& w = color_space().white;
  constexpr double delta = 6.0 / 29.0;
  auto f = [](double t) {
    return t > delta * delta * delta ? std::cbrt(t) : t / (3.0 * delta * delta) + 4.0 / 29.0;
  };
  const double fx = f(xyz[0] / w[0]), fy = f(xyz[1] / w[1]), fz = f(xyz[2] / w[2]);
  return {116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}

// Linear RGB -> L*a*b* with the Hunt adjustment a_h = 0.01 L a, b_h = 0.01 L b.
D3 linear_rgb_to_hunt_lab(const D3& rgb) {
  D3 lab = xyz_to_lab(mul(kRgbToXyz, rgb));
  lab[1] *= 0.01 * lab[0];
  lab[2] *= 0.01 * lab[0];
  return lab;
}

// HyAB distance: city-block in lightness, Euclidean in the chromatic plane.
double hyab(const D3& p, const D3& q) {
  return std::fabs(p[0] - q[0]) + std::hypot(p[1] - q[1], p[2] - q[2]);
}

// cmax = HyAB(Hunt-Lab(green), Hunt-Lab(blue))^qc: the largest colour distance of the RGB cube.
double cmax() {
  static const double v =
      std::pow(hyab(linear_rgb_to_hunt_lab({0.0, 1.0, 0.0}), linear_rgb_to_hunt_lab({0.0, 0.0, 1.0})), kQc);
  return v;
}

// Colour error remapping: [0, pc cmax) -> [0, pt) linearly, [pc cmax, cmax] -> [pt, 1].
double remap_color_error(double e) {
  const double c = cmax(), knee = kPc * c;
  return e < knee ? e * (kPt / knee) : kPt + (e - knee) / (c - knee) * (1.0 - kPt);
}

// ---- separable filtering ---------------------------------------------------------------------

using Plane = std::vector<double>;  // one channel, row-major, width x height

// dst(x, y) = sum_i k[i] src(clamp(x + i - r), y), r = (k.size() - 1) / 2 (correlation; every
// kernel here is symmetric or antisymmetric and only magnitudes of the antisymmetric ones are used).
Plane filter_rows(const Plane& src, int w, int h, const std::vector<double>& k) {
  Plane dst(src.size());
  const int r = int(k.size() / 2);
  parallel_for(h, [&](int y) {
    const double* row = src.data() + size_t(y) * size_t(w);
    for (int x = 0; x < w; ++x) {
      double s = 0;
      for (int i = -r; i <= r; ++i) s += k[size_t(i + r)] * row[std::clamp(x + i, 0, w - 1)];
      dst[size_t(y) * size_t(w) + size_t(x)] = s;
    }
  });
  return dst;
}

Plane filter_cols(const Plane& src, int w, int h, const std::vector<double>& k) {
  Plane dst(src.size());
  const int r = int(k.size() / 2);
  parallel_for(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      double s = 0;
      for (int i = -r; i <= r; ++i) s += k[size_t(i + r)] * src[size_t(std::clamp(y + i, 0, h - 1)) * size_t(w) + size_t(x)];
      dst[size_t(y) * size_t(w) + size_t(x)] = s;
    }
  });
  return dst;
}

Plane filter_2d(const Plane& src, int w, int h, const std::vector<double>& kx, const std::vector<double>& ky) {
  return filter_cols(filter_rows(src, w, h, kx), w, h, ky);
}

// ---- kernels ---------------------------------------------------------------------------------

int csf_radius(double ppd) {
  return int(std::ceil(3.0 * std::sqrt(kCsfMaxB / (2.0 * kPiD * kPiD)) * ppd));
}

// The 1-D factor of one Gaussian term of the CSF: sqrt(a sqrt(pi/b)) exp(-pi^2 x^2 / b), so that
// the product of two of them is the 2-D term a sqrt(pi/b) exp(-pi^2 (x^2 + y^2) / b).
std::vector<double> csf_term(double a, double b, int r, double ppd) {
  std::vector<double> k(size_t(2 * r + 1));
  for (int i = -r; i <= r; ++i) {
    const double x = i / ppd;  // degrees
    k[size_t(i + r)] = std::sqrt(a * std::sqrt(kPiD / b)) * std::exp(-kPiD * kPiD * x * x / b);
  }
  return k;
}

// The CSF of one channel as one or two separable terms, scaled so that the 2-D kernel
// sum_t k_t(x) k_t(y) sums to 1: the 2-D sum is sum_t S_t^2 with S_t the 1-D sums.
std::vector<std::vector<double>> csf_kernels(const CsfParams& p, int r, double ppd) {
  std::vector<std::vector<double>> terms{csf_term(p.a1, p.b1, r, ppd)};
  if (p.a2 != 0.0) terms.push_back(csf_term(p.a2, p.b2, r, ppd));
  double sum2 = 0;
  for (const auto& t : terms) {
    double s = 0;
    for (double v : t) s += v;
    sum2 += s * s;
  }
  const double scale = 1.0 / std::sqrt(sum2);
  for (auto& t : terms)
    for (double& v : t) v *= scale;
  return terms;
}

// Positive weights scaled to sum 1, negative weights to sum -1.
void normalize_signed(std::vector<double>& k) {
  double pos = 0, neg = 0;
  for (double v : k) (v > 0 ? pos : neg) += v;
  for (double& v : k) {
    if (v > 0) v /= pos;
    else if (v < 0) v /= -neg;
  }
}

struct FeatureKernels {
  std::vector<double> gauss, d1, d2;  // Gaussian (sum 1), first and second derivative
};

FeatureKernels feature_kernels(double ppd) {
  const double sigma = 0.5 * kW * ppd;
  const int r = int(std::ceil(3.0 * sigma));
  FeatureKernels f;
  double gsum = 0;
  for (int i = -r; i <= r; ++i) {
    const double x = i;
    const double g = std::exp(-x * x / (2.0 * sigma * sigma));
    gsum += g;
    f.gauss.push_back(g);
    f.d1.push_back(-x * g);                                // d/dx of the Gaussian, up to a positive factor
    f.d2.push_back((x * x / (sigma * sigma) - 1.0) * g);  // d^2/dx^2 of the Gaussian, same
  }
  for (double& v : f.gauss) v /= gsum;
  normalize_signed(f.d1);
  normalize_signed(f.d2);
  return f;
}

// ---- the pipeline ----------------------------------------------------------------------------

void check_inputs(const Image& test, const Image& ref) {
  auto check = [](const Image& img, const char* name) {
    if (img.width <= 0 || img.height <= 0 || img.pixels.empty())
      throw std::invalid_argument(std::string("FLIP: ") + name + " image is empty");
    if (img.pixels.size() != size_t(img.width) * size_t(img.height))
      throw std::invalid_argument(std::string("FLIP: ") + name + " image has " + std::to_string(img.pixels.size()) +
                                  " pixels, not width x height = " + std::to_string(img.width) + " x " +
                                  std::to_string(img.height));
    for (size_t i = 0; i < img.pixels.size(); ++i)
      if (!is_finite(img.pixels[i]))
        throw std::invalid_argument(std::string("FLIP: non-finite value in the ") + name + " image at pixel (" +
                                    std::to_string(i % size_t(img.width)) + ", " +
                                    std::to_string(i / size_t(img.width)) + ")");
  };
  check(test, "test");
  check(ref, "reference");
  if (test.width != ref.width || test.height != ref.height)
    throw std::invalid_argument("FLIP: image sizes differ: test " + std::to_string(test.width) + "x" +
                                std::to_string(test.height) + ", reference " + std::to_string(ref.width) + "x" +
                                std::to_string(ref.height));
}

void check_ppd(double ppd) {
  if (!(ppd > 0.0) || !std::isfinite(ppd))
    throw std::invalid_argument("FLIP: pixels per degree must be positive and finite, got " + std::to_string(ppd));
}

// The three YCxCz planes of an sRGB-encoded image.
std::array<Plane, 3> to_ycxcz(const Image& img) {
  std::array<Plane, 3> p;
  for (auto& c : p) c.resize(img.pixels.size());
  const int w = img.width;
  parallel_for(img.height, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      const Rgb& s = img.pixels[i];
      const D3 lin{srgb_to_linear(s.x), srgb_to_linear(s.y), srgb_to_linear(s.z)};
      const D3 o = xyz_to_ycxcz(mul(kRgbToXyz, lin));
      p[0][i] = o[0];
      p[1][i] = o[1];
      p[2][i] = o[2];
    }
  });
  return p;
}

struct CsfFilters {
  std::vector<std::vector<double>> a, rg, by;
};

// Step 1 of the colour pipeline: each opponent channel filtered with its CSF.
std::array<Plane, 3> csf_filter(const std::array<Plane, 3>& ycxcz, int w, int h, const CsfFilters& f) {
  auto apply = [&](const Plane& src, const std::vector<std::vector<double>>& terms) {
    Plane out = filter_2d(src, w, h, terms[0], terms[0]);
    for (size_t t = 1; t < terms.size(); ++t) {
      const Plane more = filter_2d(src, w, h, terms[t], terms[t]);
      for (size_t i = 0; i < out.size(); ++i) out[i] += more[i];
    }
    return out;
  };
  return {apply(ycxcz[0], f.a), apply(ycxcz[1], f.rg), apply(ycxcz[2], f.by)};
}

// Step 5: edge and point magnitudes of the normalised achromatic channel.
struct Features {
  Plane edge, point;
};

Features detect_features(const Plane& y_channel, int w, int h, const FeatureKernels& k) {
  Plane yn(y_channel.size());
  for (size_t i = 0; i < yn.size(); ++i) yn[i] = (y_channel[i] + 16.0) / 116.0;
  const Plane ex = filter_2d(yn, w, h, k.d1, k.gauss), ey = filter_2d(yn, w, h, k.gauss, k.d1);
  const Plane px = filter_2d(yn, w, h, k.d2, k.gauss), py = filter_2d(yn, w, h, k.gauss, k.d2);
  Features f{Plane(yn.size()), Plane(yn.size())};
  for (size_t i = 0; i < yn.size(); ++i) {
    f.edge[i] = std::hypot(ex[i], ey[i]);
    f.point[i] = std::hypot(px[i], py[i]);
  }
  return f;
}

// The per-pixel FLIP error (steps 1-7), in double.
std::vector<double> flip_map(const Image& test, const Image& ref, double ppd) {
  check_inputs(test, ref);
  check_ppd(ppd);
  const int w = ref.width, h = ref.height;

  const int r = csf_radius(ppd);
  const CsfFilters csf{csf_kernels(kCsfA, r, ppd), csf_kernels(kCsfRG, r, ppd), csf_kernels(kCsfBY, r, ppd)};
  const FeatureKernels fk = feature_kernels(ppd);

  const std::array<Plane, 3> ref_o = to_ycxcz(ref), test_o = to_ycxcz(test);
  const std::array<Plane, 3> ref_f = csf_filter(ref_o, w, h, csf), test_f = csf_filter(test_o, w, h, csf);
  const Features ref_feat = detect_features(ref_o[0], w, h, fk), test_feat = detect_features(test_o[0], w, h, fk);

  const M3& xyz_to_rgb = color_space().xyz_to_rgb;
  auto filtered_to_hunt_lab = [&](const std::array<Plane, 3>& p, size_t i) {
    D3 rgb = mul(xyz_to_rgb, ycxcz_to_xyz({p[0][i], p[1][i], p[2][i]}));
    for (double& c : rgb) c = std::clamp(c, 0.0, 1.0);  // step 2: clamp to the RGB cube
    return linear_rgb_to_hunt_lab(rgb);
  };

  std::vector<double> err(size_t(w) * size_t(h));
  const double inv_sqrt2 = 1.0 / std::sqrt(2.0);
  parallel_for(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      // Steps 2-4: colour difference.
      const double dc = remap_color_error(std::pow(hyab(filtered_to_hunt_lab(ref_f, i), filtered_to_hunt_lab(test_f, i)), kQc));
      // Step 6: feature difference.
      const double de = std::fabs(ref_feat.edge[i] - test_feat.edge[i]);
      const double dp = std::fabs(ref_feat.point[i] - test_feat.point[i]);
      const double df = std::min(1.0, std::pow(inv_sqrt2 * std::max(de, dp), kQf));
      // Step 7.
      err[i] = std::pow(dc, 1.0 - df);
    }
  });
  return err;
}

}  // namespace

Image flip_error_map(const Image& test_srgb, const Image& reference_srgb, float pixels_per_degree) {
  const std::vector<double> err = flip_map(test_srgb, reference_srgb, pixels_per_degree);
  Image out(reference_srgb.width, reference_srgb.height);
  for (size_t i = 0; i < err.size(); ++i) out.pixels[i] = Rgb(float(err[i]));
  return out;
}

double mean_flip(const Image& test_srgb, const Image& reference_srgb, float pixels_per_degree) {
  const std::vector<double> err = flip_map(test_srgb, reference_srgb, pixels_per_degree);
  double sum = 0;
  for (double e : err) sum += e;
  return sum / double(err.size());
}

float flip_pixels_per_degree(float distance_m, float display_width_m, int display_width_px) {
  if (!(distance_m > 0.0f) || !std::isfinite(distance_m) || !(display_width_m > 0.0f) ||
      !std::isfinite(display_width_m) || display_width_px <= 0)
    throw std::invalid_argument("flip_pixels_per_degree: distance, display width and pixel count must be positive");
  return float(double(distance_m) * (double(display_width_px) / double(display_width_m)) * kPiD / 180.0);
}

}  // namespace rl
