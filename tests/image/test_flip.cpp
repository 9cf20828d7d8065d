// Tests of src/image/flip: LDR-FLIP (Andersson et al. 2020).
//
// Besides qualitative properties (zero for identical images, monotone in the size of a difference,
// localised at a shifted edge, symmetric), two tests compare against independent, deliberately
// naive implementations written here from the paper:
//  - constant image pairs: the whole map equals the colour pipeline's remapped HyAB value of the two
//    colours, computed directly in L*a*b* (no opponent space, no filtering);
//  - small random images: a brute-force version of the full pipeline with the paper's 2-D kernels
//    (not separated), evaluated pixel by pixel.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "image/flip.h"
#include "image/tonemap.h"

using namespace rl;

namespace {

constexpr double kPiD = 3.14159265358979323846;

// ---- an independent, straightforward FLIP (doubles, decimal constants) -------------------------

struct C3 {
  double v[3];
  double operator[](int i) const { return v[i]; }
};

// Linear sRGB -> XYZ (12 decimals of the reference code's rational matrix) and XYZ -> linear RGB
// (the reference code's decimal inverse).
constexpr double kM[3][3] = {{0.412386563253, 0.357591490921, 0.180450491204},
                             {0.212636821677, 0.715182981841, 0.072180196481},
                             {0.019330620152, 0.119197163640, 0.950372587005}};
constexpr double kMinv[3][3] = {{3.241003275, -1.537398934, -0.498615861},
                                {-0.969224334, 1.875930071, 0.041554224},
                                {0.055639423, -0.204011202, 1.057148933}};

C3 mat(const double m[3][3], C3 c) {
  C3 r{};
  for (int i = 0; i < 3; ++i) r.v[i] = m[i][0] * c[0] + m[i][1] * c[1] + m[i][2] * c[2];
  return r;
}
C3 white() { return mat(kM, C3{{1, 1, 1}}); }

C3 hunt_lab_of_linear(C3 rgb) {
  const C3 xyz = mat(kM, rgb), wt = white();
  auto f = [](double t) {
    const double d = 6.0 / 29.0;
    return t > d * d * d ? std::cbrt(t) : t / (3 * d * d) + 4.0 / 29.0;
  };
  const double fx = f(xyz[0] / wt[0]), fy = f(xyz[1] / wt[1]), fz = f(xyz[2] / wt[2]);
  const double L = 116 * fy - 16, a = 500 * (fx - fy), b = 200 * (fy - fz);
  return C3{{L, 0.01 * L * a, 0.01 * L * b}};  // Hunt adjustment
}

double hyab(C3 p, C3 q) { return std::fabs(p[0] - q[0]) + std::sqrt(std::pow(p[1] - q[1], 2) + std::pow(p[2] - q[2], 2)); }

// Colour pipeline tail: HyAB^0.7 remapped with cmax = HyAB(green, blue)^0.7, pc = 0.4, pt = 0.95.
double remapped_color_error(C3 lab_a, C3 lab_b) {
  const double cmax = std::pow(hyab(hunt_lab_of_linear(C3{{0, 1, 0}}), hunt_lab_of_linear(C3{{0, 0, 1}})), 0.7);
  const double e = std::pow(hyab(lab_a, lab_b), 0.7), knee = 0.4 * cmax;
  return e < knee ? 0.95 * e / knee : 0.95 + 0.05 * (e - knee) / (cmax - knee);
}

C3 linear_of_srgb(Rgb s) { return C3{{srgb_decode(s.x), srgb_decode(s.y), srgb_decode(s.z)}}; }

// Colour error of two constant images, straight from sRGB to Hunt-adjusted L*a*b*.
double constant_pair_error(Rgb a, Rgb b) {
  return remapped_color_error(hunt_lab_of_linear(linear_of_srgb(a)), hunt_lab_of_linear(linear_of_srgb(b)));
}

// Brute-force FLIP with the paper's (non-separated) 2-D kernels.
std::vector<double> brute_force_flip(const Image& test, const Image& ref, double ppd) {
  const int w = ref.width, h = ref.height;
  auto ycxcz = [&](const Image& img) {
    std::vector<C3> o(img.pixels.size());
    const C3 wt = white();
    for (size_t i = 0; i < o.size(); ++i) {
      const C3 xyz = mat(kM, linear_of_srgb(img.pixels[i]));
      const double x = xyz[0] / wt[0], y = xyz[1] / wt[1], z = xyz[2] / wt[2];
      o[i] = C3{{116 * y - 16, 500 * (x - y), 200 * (y - z)}};
    }
    return o;
  };
  const std::vector<C3> ro = ycxcz(ref), to = ycxcz(test);
  auto px = [&](const std::vector<C3>& img, int x, int y) {
    return img[size_t(std::clamp(y, 0, h - 1) * w + std::clamp(x, 0, w - 1))];
  };

  // CSF kernels: a1 sqrt(pi/b1) exp(-pi^2 d^2/b1) + a2 sqrt(pi/b2) exp(-pi^2 d^2/b2), d in degrees.
  const double p[3][4] = {{1, 0.0047, 0, 1e-5}, {1, 0.0053, 0, 1e-5}, {34.1, 0.04, 13.5, 0.025}};
  const int r = int(std::ceil(3 * std::sqrt(0.04 / (2 * kPiD * kPiD)) * ppd));
  const int n = 2 * r + 1;
  std::vector<double> csf[3];
  for (int c = 0; c < 3; ++c) {
    double sum = 0;
    for (int j = -r; j <= r; ++j)
      for (int i = -r; i <= r; ++i) {
        const double d2 = (i * i + j * j) / (ppd * ppd);
        const double g = p[c][0] * std::sqrt(kPiD / p[c][1]) * std::exp(-kPiD * kPiD * d2 / p[c][1]) +
                         p[c][2] * std::sqrt(kPiD / p[c][3]) * std::exp(-kPiD * kPiD * d2 / p[c][3]);
        csf[c].push_back(g);
        sum += g;
      }
    for (double& g : csf[c]) g /= sum;
  }
  // Feature kernels: x-derivatives of a Gaussian, sd = 0.5 * 0.082 * ppd, +/- weights sum to +/-1.
  const double sd = 0.5 * 0.082 * ppd;
  const int fr = int(std::ceil(3 * sd)), fn = 2 * fr + 1;
  std::vector<double> edge, point;
  for (int j = -fr; j <= fr; ++j)
    for (int i = -fr; i <= fr; ++i) {
      const double g = std::exp(-(i * i + j * j) / (2 * sd * sd));
      edge.push_back(-i * g);
      point.push_back((i * i / (sd * sd) - 1) * g);
    }
  for (auto* k : {&edge, &point}) {
    double pos = 0, neg = 0;
    for (double v : *k) (v > 0 ? pos : neg) += v;
    for (double& v : *k) v = v > 0 ? v / pos : v / -neg;
  }

  std::vector<double> out(size_t(w) * size_t(h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      C3 lab[2];
      double e_mag[2], p_mag[2];
      const std::vector<C3>* imgs[2] = {&ro, &to};
      for (int m = 0; m < 2; ++m) {
        C3 f{{0, 0, 0}};
        for (int c = 0; c < 3; ++c)
          for (int j = -r; j <= r; ++j)
            for (int i = -r; i <= r; ++i) f.v[c] += csf[c][size_t((j + r) * n + i + r)] * px(*imgs[m], x + i, y + j)[c];
        const C3 wt = white();
        const double yy = (f[0] + 16) / 116;
        C3 rgb = mat(kMinv, C3{{(yy + f[1] / 500) * wt[0], yy * wt[1], (yy - f[2] / 200) * wt[2]}});
        for (double& v : rgb.v) v = std::clamp(v, 0.0, 1.0);
        lab[m] = hunt_lab_of_linear(rgb);
        double ex = 0, ey = 0, qx = 0, qy = 0;
        for (int j = -fr; j <= fr; ++j)
          for (int i = -fr; i <= fr; ++i) {
            // Gy and the y point filter are the transposes of the x filters.
            const double kx_e = edge[size_t((j + fr) * fn + i + fr)], ky_e = edge[size_t((i + fr) * fn + j + fr)];
            const double kx_p = point[size_t((j + fr) * fn + i + fr)], ky_p = point[size_t((i + fr) * fn + j + fr)];
            const double v = (px(*imgs[m], x + i, y + j)[0] + 16) / 116;
            ex += kx_e * v, ey += ky_e * v, qx += kx_p * v, qy += ky_p * v;
          }
        e_mag[m] = std::sqrt(ex * ex + ey * ey);
        p_mag[m] = std::sqrt(qx * qx + qy * qy);
      }
      const double dc = remapped_color_error(lab[0], lab[1]);
      const double df = std::min(
          1.0, std::sqrt(std::max(std::fabs(e_mag[0] - e_mag[1]), std::fabs(p_mag[0] - p_mag[1])) / std::sqrt(2.0)));
      out[size_t(y * w + x)] = std::pow(dc, 1 - df);
    }
  return out;
}

// ---- image helpers -----------------------------------------------------------------------------

Image random_image(int w, int h, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Image img(w, h);
  for (Rgb& p : img.pixels) p = Rgb(u(rng), u(rng), u(rng));
  return img;
}

// reference + uniform noise of amplitude a, clamped to [0,1].
Image perturbed(const Image& ref, float a, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-a, a);
  Image img = ref;
  for (Rgb& p : img.pixels)
    p = Rgb(std::clamp(p.x + u(rng), 0.0f, 1.0f), std::clamp(p.y + u(rng), 0.0f, 1.0f), std::clamp(p.z + u(rng), 0.0f, 1.0f));
  return img;
}

// A smooth, slightly coloured pattern with values in [0.15, 0.55].
Image smooth_pattern(int w, int h) {
  Image img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float s = 0.35f + 0.15f * std::sin(2 * float(kPiD) * x / 24.0f) * std::cos(2 * float(kPiD) * y / 16.0f);
      img.at(x, y) = Rgb(s, 0.9f * s + 0.02f, 0.8f * s + 0.05f);
    }
  return img;
}

}  // namespace

TEST_SUITE("flip") {

TEST_CASE("flip: identical images give exactly zero everywhere") {
  const Image a = random_image(40, 32, 1);
  const Image m = flip_error_map(a, a);
  REQUIRE(m.width == 40);
  REQUIRE(m.height == 32);
  int nonzero = 0;
  for (const Rgb& p : m.pixels) nonzero += (p.x != 0.0f || p.y != 0.0f || p.z != 0.0f);
  CHECK(nonzero == 0);
  CHECK(mean_flip(a, a) == 0.0);
  const Image s = smooth_pattern(33, 17);
  CHECK(mean_flip(s, s, 20.0f) == 0.0);
}

TEST_CASE("flip: black against white is close to 1 everywhere, and matches the hand-computed value") {
  const Image black(48, 40, Rgb(0.0f)), white_img(48, 40, Rgb(1.0f));
  const Image m = flip_error_map(black, white_img);
  // HyAB(white, black) = 100 (L* from 0 to 100, no chroma); 100^0.7 = 25.12 lies above the knee
  // 0.4 cmax = 16.51, so the error is 0.95 + 0.05 (25.12 - 16.51) / (cmax - 16.51) = 0.96738
  // (cmax = 203.30^0.7 = 41.276). Computed independently in Python with the same constants.
  const double expected = 0.9673797614921327;
  CHECK(constant_pair_error(Rgb(0.0f), Rgb(1.0f)) == doctest::Approx(expected).epsilon(1e-9).scale(1e-9));
  double lo = 1, hi = 0;
  for (const Rgb& p : m.pixels) {
    lo = std::min(lo, double(p.x));
    hi = std::max(hi, double(p.x));
    REQUIRE(p.x == p.y);
    REQUIRE(p.x == p.z);
  }
  CHECK(lo > 0.95);
  CHECK(lo == doctest::Approx(expected).epsilon(1e-6).scale(1e-9));
  CHECK(hi == doctest::Approx(expected).epsilon(1e-6).scale(1e-9));
}

TEST_CASE("flip: constant image pairs equal the colour pipeline's remapped HyAB value") {
  // Filtering a constant image with kernels that sum to 1 returns the constant and a constant has
  // no edges or points, so the map is the colour error of the two colours everywhere. The pairs
  // cover both branches of the remapping (below and above the knee) and the chromatic channels.
  struct Pair {
    Rgb a, b;
  };
  const Pair pairs[] = {
      {Rgb(0.5f), Rgb(0.52f)},                           // small grey step: below the knee
      {Rgb(0.2f, 0.4f, 0.6f), Rgb(0.25f, 0.4f, 0.6f)},   // red-only change
      {Rgb(0.7f, 0.3f, 0.2f), Rgb(0.3f, 0.7f, 0.2f)},    // red vs green, same blue
      {Rgb(0.1f, 0.1f, 0.9f), Rgb(0.9f, 0.9f, 0.1f)},    // blue vs yellow: above the knee
      {Rgb(0.0f, 1.0f, 0.0f), Rgb(0.0f, 0.0f, 1.0f)},    // green vs blue: cmax, error 1
  };
  for (const Pair& p : pairs) {
    CAPTURE(p.a.x);
    CAPTURE(p.b.x);
    const double expected = constant_pair_error(p.a, p.b);
    const Image ia(20, 12, p.a), ib(20, 12, p.b);
    const Image m = flip_error_map(ia, ib);
    for (const Rgb& px : m.pixels) REQUIRE(double(px.x) == doctest::Approx(expected).epsilon(1e-5).scale(1e-9));
    CHECK(mean_flip(ia, ib) == doctest::Approx(expected).epsilon(1e-5).scale(1e-9));
  }
  CHECK(constant_pair_error(Rgb(0.5f), Rgb(0.52f)) < 0.95);
  CHECK(constant_pair_error(Rgb(0.1f, 0.1f, 0.9f), Rgb(0.9f, 0.9f, 0.1f)) > 0.95);
  CHECK(mean_flip(Image(8, 8, Rgb(0, 1, 0)), Image(8, 8, Rgb(0, 0, 1))) == doctest::Approx(1.0).epsilon(1e-6).scale(1e-9));
}

TEST_CASE("flip: the separable implementation matches a brute-force one with the paper's 2-D kernels") {
  // Small images, so that the clamp-to-edge borders are exercised everywhere (the CSF radius is
  // 10 pixels at 67 ppd), at two viewing conditions.
  const Image ref = random_image(22, 18, 7);
  const Image test = perturbed(ref, 0.15f, 8);
  for (float ppd : {67.0f, 30.0f}) {
    CAPTURE(ppd);
    const Image m = flip_error_map(test, ref, ppd);
    const std::vector<double> bf = brute_force_flip(test, ref, ppd);
    double max_diff = 0, mean = 0;
    for (size_t i = 0; i < bf.size(); ++i) {
      max_diff = std::max(max_diff, std::fabs(double(m.pixels[i].x) - bf[i]));
      mean += bf[i];
    }
    mean /= double(bf.size());
    CHECK(max_diff < 2e-6);
    CHECK(mean > 0.05);  // the pair really differs: the comparison is not of two zeros
    CHECK(mean_flip(test, ref, ppd) == doctest::Approx(mean).epsilon(1e-5).scale(1e-9));
  }
}

TEST_CASE("flip: error grows monotonically with the size of a constant colour offset") {
  const Image ref = smooth_pattern(48, 48);
  const float offsets[] = {0.005f, 0.01f, 0.02f, 0.05f, 0.1f, 0.2f, 0.3f, 0.4f};
  for (int mode = 0; mode < 2; ++mode) {  // 0: grey offset (all channels), 1: red channel only
    CAPTURE(mode);
    double prev = 0;
    for (float d : offsets) {
      CAPTURE(d);
      Image test = ref;
      for (Rgb& p : test.pixels) p = mode == 0 ? p + Rgb(d) : Rgb(p.x + d, p.y, p.z);  // stays <= 0.95
      const double e = mean_flip(test, ref);
      CHECK(e > prev);
      CHECK(e < 1.0);
      prev = e;
    }
  }
}

TEST_CASE("flip: a one-pixel shift of a sharp edge gives error only around the edge") {
  // Vertical edge between dark and light grey; the test image moves it one pixel to the right, so
  // the two images differ in column 32 only. Pixels farther than the larger filter radius from that
  // column (CSF: 10, features: ceil(3 * 0.041 * 67) = 9) see identical inputs: exactly 0 there.
  const int w = 64, h = 12, edge = 32;
  Image ref(w, h), test(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      ref.at(x, y) = Rgb(x < edge ? 0.1f : 0.9f);
      test.at(x, y) = Rgb(x < edge + 1 ? 0.1f : 0.9f);
    }
  const Image m = flip_error_map(test, ref);
  // The pattern is constant along y, and so is the map (borders are clamped, not zero-padded).
  for (int y = 1; y < h; ++y)
    for (int x = 0; x < w; ++x) REQUIRE(m.at(x, y).x == m.at(x, 0).x);
  int peak = 0;
  double near = 0, total = 0;
  for (int x = 0; x < w; ++x) {
    const double e = m.at(x, 0).x;
    if (e > m.at(peak, 0).x) peak = x;
    total += e;
    if (std::abs(x - edge) <= 3) near += e;
    if (std::abs(x - edge) > 10) CHECK(e == 0.0);
  }
  CHECK(std::abs(peak - edge) <= 1);
  CHECK(m.at(peak, 0).x > 0.5);       // a clearly visible difference at the edge
  CHECK(near > 0.6 * total);          // most of the error within 3 pixels of the edge
  CHECK(m.at(edge - 8, 0).x < 0.25 * m.at(peak, 0).x);
  CHECK(m.at(edge + 8, 0).x < 0.25 * m.at(peak, 0).x);
}

TEST_CASE("flip: swapping test and reference gives the same map") {
  // Every per-pixel term of LDR-FLIP is a symmetric function of the two images' filtered values
  // (HyAB distance, |difference| of edge and point magnitudes), and both images go through the
  // same arithmetic, so the maps agree exactly, not just within a tolerance. (HDR-FLIP is not
  // symmetric: its exposure range comes from the reference. LDR-FLIP has no such step.)
  const Image a = random_image(37, 29, 11);
  const Image b = perturbed(a, 0.3f, 12);
  const Image ab = flip_error_map(a, b), ba = flip_error_map(b, a);
  int differ = 0;
  for (size_t i = 0; i < ab.size(); ++i) differ += ab.pixels[i].x != ba.pixels[i].x;
  CHECK(differ == 0);
  CHECK(mean_flip(a, b) == mean_flip(b, a));
  CHECK(mean_flip(a, b) > 0.1);
}

TEST_CASE("flip: errors lie in [0,1] for extreme image pairs") {
  const Image a = random_image(30, 30, 21), b = random_image(30, 30, 22);
  Image sat_a(30, 30), sat_b(30, 30);  // saturated corners of the RGB cube against each other
  for (int i = 0; i < 900; ++i) {
    const int c = i % 8, d = (i / 8 + 3) % 8;
    sat_a.pixels[size_t(i)] = Rgb(float(c & 1), float((c >> 1) & 1), float((c >> 2) & 1));
    sat_b.pixels[size_t(i)] = Rgb(float(d & 1), float((d >> 1) & 1), float((d >> 2) & 1));
  }
  for (const Image& m : {flip_error_map(a, b, 20.0f), flip_error_map(sat_a, sat_b, 20.0f), flip_error_map(sat_a, sat_b)}) {
    for (const Rgb& p : m.pixels) {
      REQUIRE(p.x >= 0.0f);
      REQUIRE(p.x <= 1.0f);
    }
  }
}

TEST_CASE("flip: a finer angular resolution hides high-frequency differences") {
  // A one-pixel checkerboard against plain sRGB grey 0.5. The more pixels per degree, the higher
  // the checkerboard's frequency in cycles per degree, and the more the CSFs and the feature
  // filters (both scaled with ppd) average it away. The CSFs average in linear light, so what
  // remains visible at high ppd is the difference between the checkerboard's *linear* mean and the
  // grey: zero when the two checker values are chosen with the grey's linear value as their mean,
  // and otherwise the colour error of a constant pair (grey, linear mean). Measured in the interior,
  // more than the largest filter radius (19 pixels at 134 ppd) from the borders, where clamp-to-edge
  // breaks the checkerboard.
  const int n = 96, margin = 20;
  const float lo = 0.4f, matched_hi = srgb_encode(2 * srgb_decode(0.5f) - srgb_decode(lo));
  auto interior_error = [&](float hi, float ppd) {
    Image ref(n, n, Rgb(0.5f)), test(n, n);
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) test.at(x, y) = Rgb((x + y) % 2 ? hi : lo);
    const Image m = flip_error_map(test, ref, ppd);
    double s = 0;
    for (int y = margin; y < n - margin; ++y)
      for (int x = margin; x < n - margin; ++x) s += m.at(x, y).x;
    return s / double((n - 2 * margin) * (n - 2 * margin));
  };
  // Linear-mean-matched checkerboard: visible at low ppd, invisible at high ppd.
  const double e10 = interior_error(matched_hi, 10), e20 = interior_error(matched_hi, 20);
  const double e30 = interior_error(matched_hi, 30), e67 = interior_error(matched_hi, 67);
  const double e134 = interior_error(matched_hi, 134);
  CHECK(e10 > 0.3);
  CHECK(e10 > e20);
  CHECK(e20 > e30);
  CHECK(e30 > e67);
  CHECK(e67 < 0.01);
  CHECK(e134 < 1e-3);
  // sRGB-symmetric checkerboard 0.4 / 0.6: its linear mean is brighter than grey 0.5, and at high
  // ppd the error converges to the colour error of that constant pair.
  const float mean_srgb = srgb_encode(0.5f * (srgb_decode(0.4f) + srgb_decode(0.6f)));
  const double floor = constant_pair_error(Rgb(0.5f), Rgb(mean_srgb));
  CHECK(floor > 0.05);
  CHECK(interior_error(0.6f, 134) == doctest::Approx(floor).epsilon(0.01).scale(1e-9));
  CHECK(interior_error(0.6f, 10) > 5 * floor);
}

TEST_CASE("flip: pixels per degree from viewing conditions") {
  // Paper: 0.7 m from a 0.7 m wide 3840-pixel monitor -> 67.02 pixels per degree.
  CHECK(flip_pixels_per_degree() == doctest::Approx(67.0206).epsilon(1e-5).scale(1e-9));
  CHECK(flip_pixels_per_degree(0.7f, 0.7f, 3840) == doctest::Approx(3840.0 * kPiD / 180.0).epsilon(1e-6).scale(1e-9));
  CHECK(flip_pixels_per_degree(1.4f, 0.7f, 3840) == doctest::Approx(2 * 67.0206).epsilon(1e-5).scale(1e-9));
  CHECK(flip_pixels_per_degree(0.7f, 0.7f, 1920) == doctest::Approx(0.5 * 67.0206).epsilon(1e-5).scale(1e-9));
  CHECK_THROWS_AS(flip_pixels_per_degree(0.0f), std::invalid_argument);
  CHECK_THROWS_AS(flip_pixels_per_degree(0.7f, -1.0f), std::invalid_argument);
  CHECK_THROWS_AS(flip_pixels_per_degree(0.7f, 0.7f, 0), std::invalid_argument);
}

TEST_CASE("flip: invalid inputs throw") {
  const Image a(8, 6, Rgb(0.5f)), b(6, 8, Rgb(0.5f));
  CHECK_THROWS_AS(flip_error_map(a, b), std::invalid_argument);
  CHECK_THROWS_AS(mean_flip(a, b), std::invalid_argument);
  CHECK_THROWS_AS(mean_flip(Image(), Image()), std::invalid_argument);
  CHECK_THROWS_AS(mean_flip(a, a, 0.0f), std::invalid_argument);
  CHECK_THROWS_AS(mean_flip(a, a, std::nanf("")), std::invalid_argument);
  Image bad = a;
  bad.at(3, 2) = Rgb(std::nanf(""), 0.5f, 0.5f);
  CHECK_THROWS_AS(mean_flip(bad, a), std::invalid_argument);
  Image broken = a;
  broken.pixels.pop_back();  // pixel count no longer width x height
  CHECK_THROWS_AS(mean_flip(broken, a), std::invalid_argument);
}

}  // TEST_SUITE
