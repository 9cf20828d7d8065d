#include "post/svgf.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "core/parallel.h"

namespace rl {

namespace {

// Falcor's SVGF reprojection tests (RenderPasses/SVGFPass/SVGFReproject.ps.slang, isReprjValid),
// with the depth tolerance relative instead of in scene units: a history tap is the same surface
// when its id matches, its depth is within 4 pixel-derivatives + 5% and its normal within ~25 deg.
constexpr float kDepthTolerance = 0.05f, kDepthGradients = 4.0f, kNormalCos = 0.9f;
// Schied 2017 sec. 4.2: the temporal variance is used once 4 frames of history exist.
constexpr float kMinHistoryForTemporalVariance = 4.0f;
constexpr float kMaxHistory = 32.0f;  // Falcor: history length saturates at 32 frames

bool same_surface(const Svgf::Geometry& a, const Svgf::Geometry& b) {
  return a.id == b.id && a.id != kNoSurface && std::fabs(a.z - b.z) <= kDepthTolerance * a.z + kDepthGradients * a.dz &&
         dot(a.n, b.n) >= kNormalCos;
}

// e^-e for e in [0, 40]: 2^t = 2^floor(t) (the exponent bits) x 2^frac(t) (a degree-5 Taylor
// polynomial, relative error < 2e-4). The a-trous passes take one per tap; std::exp was a third
// of their time. Plain arithmetic: the same bits on every thread count and machine.
inline float exp_neg(float e) {
  const float t = -e * 1.44269504f, fi = std::floor(t), f = t - fi;
  const float p = 1.0f + f * (0.693147181f + f * (0.240226507f + f * (0.0555041087f + f * (0.00961812911f + f * 0.00133335581f))));
  const int32_t bits = (int32_t(fi) + 127) << 23;
  float scale;
  std::memcpy(&scale, &bits, sizeof scale);
  return p * scale;
}

// max(0, n.n')^sigma_n (eq. 4): by squaring where sigma_n is a whole number (the default 128: seven
// multiplications), else through the logarithm.
inline float normal_weight(float nd, float sigma_n, int whole) {
  if (nd <= 0) return 0;
  if (whole < 0) return std::exp(sigma_n * std::log(nd));
  float r = 1, b = nd;
  for (int k = whole; k > 0; k >>= 1, b *= b)
    if (k & 1) r *= b;
  return r;
}

// Schied 2017 eq. 3-5, multiplied. inv_phi_z = 1 / (sigma_z dz |p - q|) (eq. 3's
// |grad z . (p - q)|, with dz the centre's largest derivative); inv_phi_l = 1 / (sigma_l
// sqrt(g(var)) + eps). A pixel without a surface has normal 0: weight 0. The exponential only
// where it is not negligible (e^-40).
inline float edge_weight(const Svgf::Geometry& c, const Svgf::Geometry& q, float inv_phi_z, float l, float lq,
                         float inv_phi_l, float sigma_n, int whole) {
  const float wn = normal_weight(dot(c.n, q.n), sigma_n, whole);
  if (wn == 0) return 0;
  const float e = std::fabs(c.z - q.z) * inv_phi_z + std::fabs(l - lq) * inv_phi_l;
  return e > 40 ? 0.0f : wn * exp_neg(e);
}

}  // namespace

bool Svgf::reproject(const Aovs& aovs, int x, int y, Rgb& color, Vec2& moments, float& length) const {
  if (previous_geometry_.empty()) return false;
  const size_t i = aovs.index(x, y);
  const float px = float(x) + aovs.motion[i].x, py = float(y) + aovs.motion[i].y;  // pixel centres at integers
  const int x0 = int(std::floor(px)), y0 = int(std::floor(py));
  const float fx = px - float(x0), fy = py - float(y0);
  float sum = 0;
  color = Rgb(0), moments = {0, 0}, length = 0;
  for (int t = 0; t < 4; ++t) {  // bilinear taps, each tested (Falcor: a 2x2 with per-tap validity)
    const int tx = x0 + (t & 1), ty = y0 + (t >> 1);
    if (tx < 0 || ty < 0 || tx >= width_ || ty >= height_) continue;
    const size_t j = size_t(ty) * size_t(width_) + size_t(tx);
    if (!same_surface(geometry_[i], previous_geometry_[j])) continue;
    const float w = ((t & 1) ? fx : 1 - fx) * ((t >> 1) ? fy : 1 - fy);
    color += history_color_[j] * w;
    moments = {moments.x + history_moments_[j].x * w, moments.y + history_moments_[j].y * w};
    length += previous_length_[j] * w;
    sum += w;
  }
  if (sum < 0.01f) return false;
  color = color / sum;
  moments = {moments.x / sum, moments.y / sum};
  length /= sum;
  return true;
}

// Steps 1-2: demodulation, reprojection, temporal accumulation (Schied 2017 sec. 4.1-4.2).
void Svgf::demodulate_and_accumulate(const Image& noisy, const Aovs& aovs) {
  parallel_for_pixels(width_, height_, [&](int x, int y) {
    const size_t i = aovs.index(x, y);
    Rgb d(1);
    for (int c = 0; c < 3; ++c)
      if (aovs.albedo[i][c] > 1e-3f) d[c] = aovs.albedo[i][c];
    demod_[i] = d;
    if (!aovs.valid(i)) {
      ping_[i] = {noisy.pixels[i], 0};
      moments_[i] = {0, 0};
      history_length_[i] = 0;
      return;
    }
    const Rgb illum = (noisy.pixels[i] - aovs.emission[i]) / d;
    const float l = luminance(illum);
    Rgb prev_c;
    Vec2 prev_m;
    float len = 0;
    const bool kept = reproject(aovs, x, y, prev_c, prev_m, len);
    len = kept ? std::min(len + 1, kMaxHistory) : 1;
    // alpha = max(alpha, 1 / n): a plain mean until the history is 1 / alpha frames long.
    const float a = kept ? std::max(o_.alpha, 1 / len) : 1, am = kept ? std::max(o_.moments_alpha, 1 / len) : 1;
    const Rgb c = kept ? prev_c + (illum - prev_c) * a : illum;
    const Vec2 m = kept ? Vec2{prev_m.x + (l - prev_m.x) * am, prev_m.y + (l * l - prev_m.y) * am} : Vec2{l, l * l};
    ping_[i] = {c, std::max(0.0f, m.y - m.x * m.x)};
    moments_[i] = m;
    history_length_[i] = len;
  });
}

// Step 3: where the history is shorter than 4 frames, the variance from the moments of a 7x7
// neighbourhood on the same surface (Schied 2017 sec. 4.2; weights as Falcor's
// SVGFFilterMoments: depth and normal as in the a-trous pass, luminance with sigma_l alone).
void Svgf::estimate_variance() {
  parallel_for_pixels(width_, height_, [&](int x, int y) {
    const size_t i = size_t(y) * size_t(width_) + size_t(x);
    pong_[i] = ping_[i];
    const float h = history_length_[i];
    if (geometry_[i].id == kNoSurface || h >= kMinHistoryForTemporalVariance) return;
    const float l = luminance(ping_[i].c);
    float sw = 0;
    Vec2 m{0, 0};
    Rgb c(0);
    for (int dy = -3; dy <= 3; ++dy)
      for (int dx = -3; dx <= 3; ++dx) {
        const int qx = x + dx, qy = y + dy;
        if (qx < 0 || qy < 0 || qx >= width_ || qy >= height_) continue;
        const size_t j = size_t(qy) * size_t(width_) + size_t(qx);
        const float inv_phi_z = 1 / (o_.sigma_z * geometry_[i].dz * std::max(1.0f, std::sqrt(float(dx * dx + dy * dy))));
        const float w = j == i ? 1 : edge_weight(geometry_[i], geometry_[j], inv_phi_z, l, luminance(ping_[j].c), 1 / o_.sigma_l, o_.sigma_n, whole_n_);
        sw += w;
        m = {m.x + moments_[j].x * w, m.y + moments_[j].y * w};
        c += ping_[j].c * w;
      }
    m = {m.x / sw, m.y / sw};
    // Falcor: the spatial estimate boosted by 4 / h in the first frames, where it is least reliable.
    pong_[i] = {c / sw, std::max(0.0f, m.y - m.x * m.x) * 4 / std::max(h, 1.0f)};
  });
  std::swap(ping_, pong_);
}

// Step 4, one iteration (Schied 2017 eq. 1-2): 5x5 taps of the B3 spline (1/16, 1/4, 3/8, 1/4,
// 1/16 per axis, i.e. 1, 2/3, 1/6 relative to the centre) `step` pixels apart.
void Svgf::atrous(const std::vector<Sample>& in, std::vector<Sample>& out, int step) const {
  constexpr float kH[3] = {1.0f, 2.0f / 3.0f, 1.0f / 6.0f};
  float inv_dist[3][3];  // 1 / (step |(dx, dy)|) by |dx|, |dy|
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) inv_dist[a][b] = a + b == 0 ? 0 : 1 / (float(step) * std::sqrt(float(a * a + b * b)));
  std::vector<float> lum(in.size());
  for (size_t i = 0; i < in.size(); ++i) lum[i] = luminance(in[i].c);
  parallel_for_tiles(width_, height_, [&](int x0, int y0, int x1, int y1) {
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const size_t i = size_t(y) * size_t(width_) + size_t(x);
        const Geometry& g = geometry_[i];
        if (g.id == kNoSurface) {
          out[i] = in[i];
          continue;
        }
        // The variance after a 3x3 Gaussian (1/4, 1/8, 1/16) steers the luminance weight (sec. 4.3).
        float var = 0, gw = 0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int qx = x + dx, qy = y + dy;
            if (qx < 0 || qy < 0 || qx >= width_ || qy >= height_) continue;
            const float k = (dx == 0 ? 0.5f : 0.25f) * (dy == 0 ? 0.5f : 0.25f);
            var += in[size_t(qy) * size_t(width_) + size_t(qx)].var * k;
            gw += k;
          }
        const float inv_phi_l = 1 / (o_.sigma_l * std::sqrt(std::max(var / gw, 0.0f)) + 1e-10f);
        const float inv_phi_zc = 1 / (o_.sigma_z * g.dz), l = lum[i];
        float sw = 1, sv = in[i].var;
        Rgb sc = in[i].c;
        for (int dy = -2; dy <= 2; ++dy) {
          const int qy = y + dy * step;
          if (qy < 0 || qy >= height_) continue;
          for (int dx = -2; dx <= 2; ++dx) {
            const int qx = x + dx * step;
            if ((dx == 0 && dy == 0) || qx < 0 || qx >= width_) continue;
            const size_t j = size_t(qy) * size_t(width_) + size_t(qx);
            const int ax = std::abs(dx), ay = std::abs(dy);
            const float w = kH[ax] * kH[ay] * edge_weight(g, geometry_[j], inv_phi_zc * inv_dist[ax][ay], l, lum[j], inv_phi_l, o_.sigma_n, whole_n_);
            if (w == 0) continue;
            sc += in[j].c * w;
            sv += in[j].var * w * w;
            sw += w;
          }
        }
        out[i] = {sc / sw, sv / (sw * sw)};
      }
  });
}

void Svgf::denoise(const Image& noisy, const Aovs& aovs, Image& out) {
  if (noisy.width != width_ || noisy.height != height_) {  // a new size: no history
    width_ = noisy.width, height_ = noisy.height;
    const size_t n = noisy.size();
    previous_geometry_.clear();
    geometry_.assign(n, {}), demod_.assign(n, Rgb(1)), history_color_.assign(n, Rgb(0));
    history_moments_.assign(n, {0, 0}), moments_.assign(n, {0, 0});
    history_length_.assign(n, 0), previous_length_.assign(n, 0);
    ping_.assign(n, {}), pong_.assign(n, {});
  }
  geometry_.resize(noisy.size());  // (it held the frame before last: swapped below)
  for (size_t i = 0; i < noisy.size(); ++i)
    geometry_[i] = {aovs.normal[i], aovs.depth[i], std::max(aovs.depth_gradient[i], 1e-4f * aovs.depth[i]), aovs.surface_id[i]};
  std::swap(previous_length_, history_length_);
  demodulate_and_accumulate(noisy, aovs);
  estimate_variance();
  for (int it = 0; it < o_.atrous_iterations; ++it) {
    atrous(ping_, pong_, 1 << it);
    if (it == 0)  // the first iteration's output is the colour history (sec. 4.3)
      for (size_t i = 0; i < pong_.size(); ++i) history_color_[i] = pong_[i].c;
    std::swap(ping_, pong_);
  }
  out = Image(width_, height_);
  for (size_t i = 0; i < out.size(); ++i)
    out.pixels[i] = aovs.valid(i) ? ping_[i].c * demod_[i] + aovs.emission[i] : noisy.pixels[i];
  std::swap(history_moments_, moments_);
  std::swap(previous_geometry_, geometry_);
}

}  // namespace rl
