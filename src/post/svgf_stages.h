// SVGF's per-pixel math (Schied et al. 2017, "Spatiotemporal Variance-Guided Filtering", HPG
// 2017), written once for the host and the device (RESTIR_HD, ARCHITECTURE.md "Backends"): the
// reprojection with its consistency tests, the temporal accumulation of colour and luminance
// moments, the variance (with the 7x7 estimate for short histories), one a-trous iteration's pixel
// and the re-modulation. Two drivers call these same functions:
//   - Svgf (svgf.cpp), the CPU's fast filter, a row at a time over planar copies: its vectorised
//     loops call the tap functions below (edge_weight, tap_inv_distance, b3_weight, ...) per lane;
//   - SvgfStages<Exec> (svgf_driver.h), one kernel per stage through an execution policy: the
//     host twin (render.backend = cpu-bvh) and CUDA (svgf_stages.cu, --fmad=false).
// Both sum each pixel's taps in the same order with the same expressions, so they give the same
// floats (tests/post/test_svgf_stages.cpp). The only host/device difference left: a sigma_n that
// is not a power of two takes powf on the device, std::pow on the host.
#pragma once
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "core/math.h"
#include "frame/aov.h"
#include "frame/options.h"

namespace rl::svgf {

// Falcor's SVGF reprojection tests (RenderPasses/SVGFPass/SVGFReproject.ps.slang, isReprjValid),
// with the depth tolerance relative instead of in scene units: a history tap is the same surface
// when its id matches, its depth is within 4 pixel-derivatives + 5% and its normal within ~25 deg.
inline constexpr float kDepthTolerance = 0.05f, kDepthGradients = 4.0f, kNormalCos = 0.9f;
// Schied 2017 sec. 4.2: the temporal variance is used once 4 frames of history exist.
inline constexpr float kMinHistoryForTemporalVariance = 4.0f;
inline constexpr float kMaxHistory = 32.0f;  // Falcor: history length saturates at 32 frames
// The normal weight's exponent (eq. 4) as a template argument K of edge_weight: K >= 0 squarings
// (sigma_n = 2^K, the vectorised rows' case), kPow: std::pow, kRuntime: `squarings` squarings when
// it is >= 0, else pow (the per-pixel kernels: one instantiation for every sigma_n).
inline constexpr int kPow = -1, kRuntime = -2;

// The filter's parameters as the stages read them (DenoiseOptions holds a std::string).
struct Params {
  float sigma_z = 1, sigma_n = 128, sigma_l = 4, alpha = 0.2f, moments_alpha = 0.2f;
  int squarings = 7;  // sigma_n = 2^squarings (1 <= sigma_n <= 1024), else -1
};
// K with sigma_n = 2^K, 1 <= sigma_n <= 1024 (the normal weight by K squarings); else -1.
inline int squarings_of(float sigma_n) {
  for (int k = 0; k <= 10; ++k)
    if (sigma_n == float(1 << k)) return k;
  return -1;
}
inline Params params_of(const DenoiseOptions& o) {
  return {o.sigma_z, o.sigma_n, o.sigma_l, o.alpha, o.moments_alpha, squarings_of(o.sigma_n)};
}

// Demodulated illumination and its variance: what the a-trous passes filter.
struct Sample {
  Rgb c;
  float var = 0;
};
// The current frame's geometry as the edge-stopping functions read it.
struct Geometry {
  Vec3 n;
  float z = 0;
  float dz = 0;  // max(depth_gradient, 1e-4 z): a plane facing the camera still has a scale
  uint32_t id = kNoSurface;
};

RESTIR_HD inline Geometry make_geometry(Vec3 normal, float depth, float depth_gradient, uint32_t id) {
  return {normal, depth, std::max(depth_gradient, 1e-4f * depth), id};
}
// Eq. 3's denominator inverted once a frame: 1 / (sigma_z dz); 0 without a surface.
RESTIR_HD inline float inv_depth_scale(const Geometry& g, float sigma_z) { return g.id == kNoSurface ? 0.0f : 1 / (sigma_z * g.dz); }

RESTIR_HD inline bool same_surface(const Geometry& a, const Geometry& b) {
  return a.id == b.id && a.id != kNoSurface && std::fabs(a.z - b.z) <= kDepthTolerance * a.z + kDepthGradients * a.dz &&
         dot(a.n, b.n) >= kNormalCos;
}

// Sec. 4, albedo demodulation: what radiance is divided by (albedo, 1 where a channel is ~0).
RESTIR_HD inline Rgb demodulator(Rgb albedo) {
  Rgb d(1);
  for (int c = 0; c < 3; ++c)
    if (albedo[c] > 1e-3f) d[c] = albedo[c];
  return d;
}
// Step 5, re-modulation: radiance = illumination x albedo + emission.
RESTIR_HD inline Rgb remodulate(Rgb illumination, Rgb demod, Rgb emission) { return illumination * demod + emission; }

RESTIR_HD inline int32_t float_bits(float f) {
#ifdef __CUDA_ARCH__
  return __float_as_int(f);
#else
  return std::bit_cast<int32_t>(f);
#endif
}
RESTIR_HD inline float bits_float(int32_t i) {
#ifdef __CUDA_ARCH__
  return __int_as_float(i);
#else
  return std::bit_cast<float>(i);
#endif
}

// e^-e for e in [0, 40]: 2^t = 2^n (the exponent bits) x 2^f, n = round(t), f = t - n in
// [-1/2, 1/2] (a degree-5 Taylor polynomial, relative error < 3e-6). n by the 1.5 x 2^23 trick:
// only float adds and integer bit operations, which SSE2 vectorises (a float-to-int conversion in
// the loop kept GCC from it). The a-trous passes take one per tap; std::exp was a third of their
// time. Plain arithmetic: the same bits on every thread count, machine and device (--fmad=false).
RESTIR_HD inline float exp_neg(float e) {
  constexpr float kMagic = 12582912.0f;  // 1.5 x 2^23: adding it rounds to an integer in the low mantissa bits
  const float t = -e * 1.44269504f, y = t + kMagic, f = t - (y - kMagic);
  const int32_t n = float_bits(y) - float_bits(kMagic);
  const float p = 1.0f + f * (0.693147181f + f * (0.240226507f + f * (0.0555041087f + f * (0.00961812911f + f * 0.00133335581f))));
  return p * bits_float((n + 127) << 23);
}

RESTIR_HD inline float pow_hd(float x, float y) {
#ifdef __CUDA_ARCH__
  return powf(x, y);
#else
  return std::pow(x, y);
#endif
}

// Schied 2017 eq. 3-5, multiplied, times the kernel weight k: w = k max(0, n.n')^sigma_n
// exp(-|z - z'| / (sigma_z dz |p - q|) - |l - l'| ipl) (eq. 3's |grad z . (p - q)| as the centre's
// largest derivative dz times the tap distance; ipz = inv_depth_scale, ipl = eq. 5's luminance
// denominator inverted); 0 where the exponent passes 40. The 7x7 moments estimate passes k = 1
// (1 x wn is wn exactly). Centre c*, tap q*; K: see kPow / kRuntime.
template <int K>
RESTIR_HD inline float edge_weight(float cnx, float cny, float cnz, float cz, float cl, float cipz, float cipl, float qnx, float qny,
                                   float qnz, float qz, float ql, float k, float inv_dist, float sigma_n, int squarings) {
  const float nd = cnx * qnx + cny * qny + cnz * qnz;
  float wn = nd > 0 ? nd : 0.0f;  // eq. 4 (a pixel without a surface has normal 0)
  if constexpr (K >= 0) {
    for (int t = 0; t < K; ++t) wn *= wn;
  } else if (K == kRuntime && squarings >= 0) {
    for (int t = 0; t < squarings; ++t) wn *= wn;
  } else {
    wn = wn > 0 ? pow_hd(wn, sigma_n) : 0.0f;
  }
  const float e = std::fabs(cz - qz) * (cipz * inv_dist) + std::fabs(cl - ql) * cipl;  // eq. 3, 5
  return e > 40 ? 0.0f : k * wn * exp_neg(std::min(e, 40.0f));
}

// 1 / |p - q| for the tap (dx, dy) `step` pixels apart (eq. 3's distance).
RESTIR_HD inline float tap_inv_distance(int step, int dx, int dy) { return 1 / (float(step) * std::sqrt(float(dx * dx + dy * dy))); }
// Eq. 1's h: the B3 spline (1/16, 1/4, 3/8, 1/4, 1/16 per axis), i.e. 1, 2/3, 1/6 relative to the centre.
RESTIR_HD inline float b3_weight(int dx, int dy) {
  const float h[3] = {1.0f, 2.0f / 3.0f, 1.0f / 6.0f};
  return h[dx < 0 ? -dx : dx] * h[dy < 0 ? -dy : dy];
}
// Sec. 4.3's 3x3 Gaussian (1/4, 1/8, 1/16) over the variance: a tap's weight.
RESTIR_HD inline float gaussian_weight(int dx, int dy) { return (dx == 0 ? 0.5f : 0.25f) * (dy == 0 ? 0.5f : 0.25f); }
// Eq. 5's denominator inverted: 1 / (sigma_l sqrt(g(var)) + eps), g(var) = the Gaussian's sum /
// its weight (renormalised where the 3x3 leaves the image).
RESTIR_HD inline float luminance_scale(float sigma_l, float gaussian_sum, float gaussian_weight_sum) {
  return 1 / (sigma_l * std::sqrt(std::max(gaussian_sum / gaussian_weight_sum, 0.0f)) + 1e-10f);
}
// Eq. 1-2's normalisation: the colour by the weight sum, the variance by its square.
RESTIR_HD inline Sample atrous_result(float r, float g, float b, float var, float w) { return {Rgb(r, g, b) / w, var / (w * w)}; }
// Sec. 4.2: variance = m2 - m1^2 from the 7x7 sums; Falcor boosts it by 4 / h in the first
// frames, where the spatial estimate is least reliable.
RESTIR_HD inline Sample moments_result(float r, float g, float b, float m1_sum, float m2_sum, float w, float history) {
  const float m1 = m1_sum / w, m2 = m2_sum / w;
  return {Rgb(r, g, b) / w, std::max(0.0f, m2 - m1 * m1) * 4 / std::max(history, 1.0f)};
}

// The previous frame's state at pixel j, as reproject reads it: H gives geometry(j), color(j),
// moments(j), length(j) (svgf.cpp: arrays of structs; svgf_driver.h: planes).
// Reprojection through the motion vector (sec. 4.1): a bilinear 2x2 footprint whose taps each must
// pass same_surface (Falcor: per-tap validity), renormalised over those that pass; false (history
// dropped) below 1% of it. Pixel centres at integers.
template <class H>
RESTIR_HD inline bool reproject(const H& history, const Geometry& g, Vec2 motion, int x, int y, int width, int height, Rgb& color,
                                Vec2& moments, float& length) {
  const float px = float(x) + motion.x, py = float(y) + motion.y;
  const int x0 = int(std::floor(px)), y0 = int(std::floor(py));
  const float fx = px - float(x0), fy = py - float(y0);
  float sum = 0;
  color = Rgb(0), moments = {0, 0}, length = 0;
  for (int t = 0; t < 4; ++t) {
    const int tx = x0 + (t & 1), ty = y0 + (t >> 1);
    if (tx < 0 || ty < 0 || tx >= width || ty >= height) continue;
    const size_t j = size_t(ty) * size_t(width) + size_t(tx);
    if (!same_surface(g, history.geometry(j))) continue;
    const float w = ((t & 1) ? fx : 1 - fx) * ((t >> 1) ? fy : 1 - fy);
    color += history.color(j) * w;
    const Vec2 m = history.moments(j);
    moments = {moments.x + m.x * w, moments.y + m.y * w};
    length += history.length(j) * w;
    sum += w;
  }
  if (sum < 0.01f) return false;
  color = color / sum;
  moments = {moments.x / sum, moments.y / sum};
  length /= sum;
  return true;
}

// One pixel's temporal stage (steps 1-3 without the 7x7 estimate): its sample (colour, variance
// m2 - m1^2), moments and history length.
struct Temporal {
  Sample s;
  Vec2 moments;
  float length = 0;
};
// The pixel (x, y) of the current frame: its radiance, albedo, emission, motion and geometry g;
// history: the previous frame's (null: none, the first frame or a new size); lambda: A-SVGF's
// (Schied et al. 2018, eq. 9) for this pixel, null without.
template <class H>
RESTIR_HD inline Temporal temporal_pixel(const H* history, int x, int y, int width, int height, Rgb noisy, Rgb albedo, Rgb emission,
                                         Vec2 motion, const Geometry& g, const float* lambda, const Params& p) {
  if (g.id == kNoSurface) return {{noisy, 0}, {0, 0}, 0};  // the environment passes through
  const Rgb illum = (noisy - emission) / demodulator(albedo);
  const float l = luminance(illum);
  Rgb prev_c;
  Vec2 prev_m;
  float len = 0;
  const bool kept = history && reproject(*history, g, motion, x, y, width, height, prev_c, prev_m, len);
  len = kept ? std::min(len + 1, float(kMaxHistory)) : 1;  // (a copy: device code cannot bind the constant)
  // Sec. 4.1-4.2: alpha = max(alpha, 1 / n), a plain mean until the history is 1 / alpha frames long.
  float a = kept ? std::max(p.alpha, 1 / len) : 1, am = kept ? std::max(p.moments_alpha, 1 / len) : 1;
  if (lambda) {  // A-SVGF: the temporal gradient shortens the history where the lighting changed
    a = (1 - *lambda) * a + *lambda;
    am = (1 - *lambda) * am + *lambda;
  }
  const Rgb c = kept ? prev_c + (illum - prev_c) * a : illum;
  const Vec2 m = kept ? Vec2{prev_m.x + (l - prev_m.x) * am, prev_m.y + (l * l - prev_m.y) * am} : Vec2{l, l * l};
  return {{c, std::max(0.0f, m.y - m.x * m.x)}, m, len};
}

// Planes (structure of arrays) of one frame's geometry, as the per-pixel filter reads them.
struct GeometryPlanes {
  const float *nx, *ny, *nz, *z, *ipz;
  const uint32_t* id;
};
// Planes of a filtered quantity: colour, luminance of that colour, and the variance (in the 7x7
// estimate: the first moment, m2 beside it).
struct SamplePlanes {
  const float *r, *g, *b, *l, *var, *m2;
};

// Step 3's 7x7 estimate at pixel i = (x, y) (sec. 4.2; weights as Falcor's SVGFFilterMoments:
// depth and normal as in the a-trous pass, luminance with sigma_l alone, no kernel), for a pixel
// with a surface and a history shorter than 4 frames; taps summed row by row as Svgf's rows do.
RESTIR_HD inline Sample moments_pixel(const GeometryPlanes& g, const SamplePlanes& s, int x, int y, int width, int height,
                                      float history, const Params& p) {
  const size_t i = size_t(y) * size_t(width) + size_t(x);
  const float ipl = 1 / p.sigma_l;
  float sr = s.r[i], sg = s.g[i], sb = s.b[i], s1 = s.var[i], s2 = s.m2[i], sw = 1;
  for (int dy = -3; dy <= 3; ++dy) {
    const int qy = y + dy;
    if (qy < 0 || qy >= height) continue;
    for (int dx = -3; dx <= 3; ++dx) {
      const int qx = x + dx;
      if ((dx == 0 && dy == 0) || qx < 0 || qx >= width) continue;
      const size_t q = size_t(qy) * size_t(width) + size_t(qx);
      const float wt = edge_weight<kRuntime>(g.nx[i], g.ny[i], g.nz[i], g.z[i], s.l[i], g.ipz[i], ipl, g.nx[q], g.ny[q], g.nz[q], g.z[q],
                                             s.l[q], 1.0f, tap_inv_distance(1, dx, dy), p.sigma_n, p.squarings);
      sr += wt * s.r[q], sg += wt * s.g[q], sb += wt * s.b[q];
      s1 += wt * s.var[q];
      s2 += wt * s.m2[q];
      sw += wt;
    }
  }
  return moments_result(sr, sg, sb, s1, s2, sw, history);
}

// Step 4, one a-trous iteration's pixel i = (x, y) with a surface (eq. 1-2): the 3x3 Gaussian of
// the variance for eq. 5, then 5x5 B3 taps `step` pixels apart weighted by eq. 3-5, the variance
// by the squared weights; the centre first, then the taps row by row, as Svgf's rows sum them.
RESTIR_HD inline Sample atrous_pixel(const GeometryPlanes& g, const SamplePlanes& s, int x, int y, int width, int height, int step,
                                     const Params& p) {
  const size_t i = size_t(y) * size_t(width) + size_t(x);
  float gv = 0, gw = 0;
  for (int dy = -1; dy <= 1; ++dy) {
    const int qy = y + dy;
    if (qy < 0 || qy >= height) continue;
    for (int dx = -1; dx <= 1; ++dx) {
      const int qx = x + dx;
      if (qx < 0 || qx >= width) continue;
      const float k = gaussian_weight(dx, dy);
      gv += k * s.var[size_t(qy) * size_t(width) + size_t(qx)];
      gw += k;
    }
  }
  const float ipl = luminance_scale(p.sigma_l, gv, gw);
  float sr = s.r[i], sg = s.g[i], sb = s.b[i], sv = s.var[i], sw = 1;
  for (int dy = -2; dy <= 2; ++dy) {
    const int qy = y + dy * step;
    if (qy < 0 || qy >= height) continue;
    for (int dx = -2; dx <= 2; ++dx) {
      const int qx = x + dx * step;
      if ((dx == 0 && dy == 0) || qx < 0 || qx >= width) continue;
      const size_t q = size_t(qy) * size_t(width) + size_t(qx);
      const float wt = edge_weight<kRuntime>(g.nx[i], g.ny[i], g.nz[i], g.z[i], s.l[i], g.ipz[i], ipl, g.nx[q], g.ny[q], g.nz[q], g.z[q],
                                             s.l[q], b3_weight(dx, dy), tap_inv_distance(step, dx, dy), p.sigma_n, p.squarings);
      sr += wt * s.r[q], sg += wt * s.g[q], sb += wt * s.b[q];
      sv += wt * wt * s.var[q];
      sw += wt;
    }
  }
  return atrous_result(sr, sg, sb, sv, sw);
}

}  // namespace rl::svgf
