#include "post/svgf.h"

#include <algorithm>
#include <cmath>

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

// Schied 2017 eq. 3-5, multiplied: w_z w_n w_l as one exponential. `dist` is the tap's distance in
// pixels (eq. 3's |grad z . (p - q)| ~ dz |p - q|); inv_phi_l = 1 / (sigma_l sqrt(var) + eps).
float edge_weight(const Svgf::Geometry& c, const Svgf::Geometry& q, float dist, float l, float lq, float inv_phi_l,
                  const DenoiseOptions& o) {
  if (q.id == kNoSurface) return 0;
  const float nd = dot(c.n, q.n);
  if (nd <= 0) return 0;
  const float wz = std::fabs(c.z - q.z) / (o.sigma_z * c.dz * dist);
  const float wl = std::fabs(l - lq) * inv_phi_l;
  return std::exp(o.sigma_n * std::log(nd) - wz - wl);  // max(0, n.n')^sigma_n exp(-wz - wl)
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
        const float dist = std::max(1.0f, std::sqrt(float(dx * dx + dy * dy)));
        const float w = j == i ? 1 : edge_weight(geometry_[i], geometry_[j], dist, l, luminance(ping_[j].c), 1 / o_.sigma_l, o_);
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
  parallel_for_pixels(width_, height_, [&](int x, int y) {
    const size_t i = size_t(y) * size_t(width_) + size_t(x);
    const Geometry& g = geometry_[i];
    if (g.id == kNoSurface) {
      out[i] = in[i];
      return;
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
    const float l = luminance(in[i].c);
    float sw = 1, sv = in[i].var;
    Rgb sc = in[i].c;
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx) {
        const int qx = x + dx * step, qy = y + dy * step;
        if ((dx == 0 && dy == 0) || qx < 0 || qy < 0 || qx >= width_ || qy >= height_) continue;
        const size_t j = size_t(qy) * size_t(width_) + size_t(qx);
        const float dist = float(step) * std::sqrt(float(dx * dx + dy * dy));
        const float w = kH[std::abs(dx)] * kH[std::abs(dy)] * edge_weight(g, geometry_[j], dist, l, luminance(in[j].c), inv_phi_l, o_);
        sc += in[j].c * w;
        sv += in[j].var * w * w;
        sw += w;
      }
    out[i] = {sc / sw, sv / (sw * sw)};
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
