#include "post/svgf.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <bit>

#include "core/parallel.h"
#include "core/widest.h"

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

// e^-e for e in [0, 40]: 2^t = 2^n (the exponent bits) x 2^f, n = round(t), f = t - n in
// [-1/2, 1/2] (a degree-5 Taylor polynomial, relative error < 3e-6). n by the 1.5 x 2^23 trick:
// only float adds and integer bit operations, which SSE2 vectorises (a float-to-int conversion in
// the loop kept GCC from it). The a-trous passes take one per tap; std::exp was a third of their
// time. Plain arithmetic: the same bits on every thread count and machine.
inline float exp_neg(float e) {
  constexpr float kMagic = 12582912.0f;  // 1.5 x 2^23: adding it rounds to an integer in the low mantissa bits
  const float t = -e * 1.44269504f, y = t + kMagic, f = t - (y - kMagic);
  const int32_t n = std::bit_cast<int32_t>(y) - std::bit_cast<int32_t>(kMagic);
  const float p = 1.0f + f * (0.693147181f + f * (0.240226507f + f * (0.0555041087f + f * (0.00961812911f + f * 0.00133335581f))));
  return p * std::bit_cast<float>((n + 127) << 23);
}

// One tap of an a-trous row for n pixels: the centres c, their taps q, the sums s. Separate arrays
// the compiler is told do not alias (__restrict), so that it vectorises the loop without
// run-time overlap checks (it gives up above ten of them).
struct CentreRow {
  const float *__restrict nx, *__restrict ny, *__restrict nz, *__restrict z, *__restrict l, *__restrict ipz, *__restrict ipl;
};
struct TapRow {
  const float *__restrict nx, *__restrict ny, *__restrict nz, *__restrict z, *__restrict l, *__restrict var,
      *__restrict r, *__restrict g, *__restrict b;
};
struct SumRow {
  float *__restrict r, *__restrict g, *__restrict b, *__restrict var, *__restrict w;
};
// One tap of the 3x3 Gaussian over n pixels of a row: sum += k var, weight += k.
inline void gaussian_tap(const float* __restrict var, float* __restrict sum, float* __restrict weight, int n, float k) {
  for (int x = 0; x < n; ++x) {
    sum[x] += k * var[x];
    weight[x] += k;
  }
}

// Schied 2017 eq. 3-5, multiplied, times the B3 kernel k: w = k max(0, n.n')^sigma_n
// exp(-|z - z'| / (sigma_z dz |p - q|) - |l - l'| / (sigma_l sqrt(g(var)) + eps)) (eq. 3's
// |grad z . (p - q)| as the centre's largest derivative dz times the tap distance; ipz =
// 1 / (sigma_z dz), 0 without a surface; ipl = the luminance denominator's inverse); 0 where the
// exponent passes 40. K: sigma_n = 2^K by K squarings; K < 0: std::pow (not vectorised).
template <int K>
inline void atrous_taps(CentreRow c, TapRow q, SumRow s, int n, float k, float inv_dist, float sigma_n) {
  for (int x = 0; x < n; ++x) {
    const float nd = c.nx[x] * q.nx[x] + c.ny[x] * q.ny[x] + c.nz[x] * q.nz[x];
    float wn = nd > 0 ? nd : 0.0f;  // eq. 4 (a pixel without a surface has normal 0)
    if constexpr (K >= 0)
      for (int t = 0; t < K; ++t) wn *= wn;
    else
      wn = wn > 0 ? std::pow(wn, sigma_n) : 0.0f;
    const float e = std::fabs(c.z[x] - q.z[x]) * (c.ipz[x] * inv_dist) + std::fabs(c.l[x] - q.l[x]) * c.ipl[x];  // eq. 3, 5
    const float wt = e > 40 ? 0.0f : k * wn * exp_neg(std::min(e, 40.0f));
    s.r[x] += wt * q.r[x], s.g[x] += wt * q.g[x], s.b[x] += wt * q.b[x];
    s.var[x] += wt * wt * q.var[x];
    s.w[x] += wt;
  }
}

// atrous_taps for sigma_n = 2^K, compiled for AVX2 too (core/widest.h: the copy the CPU runs is
// picked at load time; both compute the same floats). 8 pixels a vector instead of 4.
RL_WIDEST void atrous_taps_pow2(CentreRow c, TapRow q, SumRow s, int n, float k, float inv_dist, int squarings) {
  switch (squarings) {
    case 0: return atrous_taps<0>(c, q, s, n, k, inv_dist, 1);
    case 1: return atrous_taps<1>(c, q, s, n, k, inv_dist, 2);
    case 2: return atrous_taps<2>(c, q, s, n, k, inv_dist, 4);
    case 3: return atrous_taps<3>(c, q, s, n, k, inv_dist, 8);
    case 4: return atrous_taps<4>(c, q, s, n, k, inv_dist, 16);
    case 5: return atrous_taps<5>(c, q, s, n, k, inv_dist, 32);
    case 6: return atrous_taps<6>(c, q, s, n, k, inv_dist, 64);
    case 7: return atrous_taps<7>(c, q, s, n, k, inv_dist, 128);
    case 8: return atrous_taps<8>(c, q, s, n, k, inv_dist, 256);
    case 9: return atrous_taps<9>(c, q, s, n, k, inv_dist, 512);
    default: return atrous_taps<10>(c, q, s, n, k, inv_dist, 1024);
  }
}

// One tap of the 7x7 moments estimate for n pixels (weights as atrous_taps, no kernel): the
// colour, the two moments and the weight summed.
struct MomentRow {
  const float *__restrict nx, *__restrict ny, *__restrict nz, *__restrict z, *__restrict l, *__restrict m1,
      *__restrict m2, *__restrict r, *__restrict g, *__restrict b;
};
template <int K>
inline void moment_taps(CentreRow c, MomentRow q, SumRow s, float* __restrict m2, int n, float inv_dist, float sigma_n) {
  for (int x = 0; x < n; ++x) {
    const float nd = c.nx[x] * q.nx[x] + c.ny[x] * q.ny[x] + c.nz[x] * q.nz[x];
    float wn = nd > 0 ? nd : 0.0f;
    if constexpr (K >= 0)
      for (int t = 0; t < K; ++t) wn *= wn;
    else
      wn = wn > 0 ? std::pow(wn, sigma_n) : 0.0f;
    const float e = std::fabs(c.z[x] - q.z[x]) * (c.ipz[x] * inv_dist) + std::fabs(c.l[x] - q.l[x]) * c.ipl[x];
    const float wt = e > 40 ? 0.0f : wn * exp_neg(std::min(e, 40.0f));
    s.r[x] += wt * q.r[x], s.g[x] += wt * q.g[x], s.b[x] += wt * q.b[x];
    s.var[x] += wt * q.m1[x];  // (the first moment's sum)
    m2[x] += wt * q.m2[x];
    s.w[x] += wt;
  }
}
RL_WIDEST void moment_taps_pow2(CentreRow c, MomentRow q, SumRow s, float* m2, int n, float inv_dist, int squarings) {
  switch (squarings) {
    case 0: return moment_taps<0>(c, q, s, m2, n, inv_dist, 1);
    case 1: return moment_taps<1>(c, q, s, m2, n, inv_dist, 2);
    case 2: return moment_taps<2>(c, q, s, m2, n, inv_dist, 4);
    case 3: return moment_taps<3>(c, q, s, m2, n, inv_dist, 8);
    case 4: return moment_taps<4>(c, q, s, m2, n, inv_dist, 16);
    case 5: return moment_taps<5>(c, q, s, m2, n, inv_dist, 32);
    case 6: return moment_taps<6>(c, q, s, m2, n, inv_dist, 64);
    case 7: return moment_taps<7>(c, q, s, m2, n, inv_dist, 128);
    case 8: return moment_taps<8>(c, q, s, m2, n, inv_dist, 256);
    case 9: return moment_taps<9>(c, q, s, m2, n, inv_dist, 512);
    default: return moment_taps<10>(c, q, s, m2, n, inv_dist, 1024);
  }
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
    float a = kept ? std::max(o_.alpha, 1 / len) : 1, am = kept ? std::max(o_.moments_alpha, 1 / len) : 1;
    if (!lambda_.empty()) {  // A-SVGF: the temporal gradient shortens the history where the lighting changed
      a = (1 - lambda_[i]) * a + lambda_[i];
      am = (1 - lambda_[i]) * am + lambda_[i];
    }
    const Rgb c = kept ? prev_c + (illum - prev_c) * a : illum;
    const Vec2 m = kept ? Vec2{prev_m.x + (l - prev_m.x) * am, prev_m.y + (l * l - prev_m.y) * am} : Vec2{l, l * l};
    ping_[i] = {c, std::max(0.0f, m.y - m.x * m.x)};
    moments_[i] = m;
    history_length_[i] = len;
  });
}

// Step 3: where the history is shorter than 4 frames, the variance from the moments of a 7x7
// neighbourhood on the same surface (Schied 2017 sec. 4.2; weights as Falcor's
// SVGFFilterMoments: depth and normal as in the a-trous pass, luminance with sigma_l alone, no
// kernel), a row at a time as the a-trous passes. Skipped when every pixel has 4 frames.
void Svgf::estimate_variance() {
  bool any = false;
  for (size_t i = 0; i < ping_.size() && !any; ++i) any = geometry_[i].id != kNoSurface && history_length_[i] < kMinHistoryForTemporalVariance;
  if (!any) return;
  for (size_t i = 0; i < ping_.size(); ++i) {
    plane_r_[i] = ping_[i].c.x, plane_g_[i] = ping_[i].c.y, plane_b_[i] = ping_[i].c.z, plane_l_[i] = luminance(ping_[i].c);
    plane_var_[i] = moments_[i].x, plane_m2_[i] = moments_[i].y;  // (plane_var_ holds the first moment here)
  }
  parallel_for(height_, [&](int y) { moments_row(y); });
  std::swap(ping_, pong_);
}

void Svgf::moments_row(int y) {
  const int w = width_;
  const size_t row = size_t(y) * size_t(w);
  std::vector<float> acc(size_t(w) * 7);
  float *sr = acc.data(), *sg = sr + w, *sb = sg + w, *s1 = sb + w, *s2 = s1 + w, *sw = s2 + w, *ipl = sw + w;
  for (int x = 0; x < w; ++x) {  // the centre, weight 1
    const size_t i = row + size_t(x);
    sr[x] = plane_r_[i], sg[x] = plane_g_[i], sb[x] = plane_b_[i], s1[x] = plane_var_[i], s2[x] = plane_m2_[i], sw[x] = 1;
    ipl[x] = 1 / o_.sigma_l;
  }
  const CentreRow c{plane_nx_.data() + row, plane_ny_.data() + row, plane_nz_.data() + row, plane_z_.data() + row,
                    plane_l_.data() + row, plane_ipz_.data() + row, ipl};
  for (int dy = -3; dy <= 3; ++dy) {
    const int qy = y + dy;
    if (qy < 0 || qy >= height_) continue;
    for (int dx = -3; dx <= 3; ++dx) {
      if (dx == 0 && dy == 0) continue;
      const int x0 = std::max(0, -dx), x1 = std::min(w, w - dx);
      const size_t q = size_t(qy) * size_t(w) + size_t(dx + x0);
      const MomentRow m{plane_nx_.data() + q, plane_ny_.data() + q, plane_nz_.data() + q, plane_z_.data() + q, plane_l_.data() + q,
                        plane_var_.data() + q, plane_m2_.data() + q, plane_r_.data() + q, plane_g_.data() + q, plane_b_.data() + q};
      const CentreRow cx{c.nx + x0, c.ny + x0, c.nz + x0, c.z + x0, c.l + x0, c.ipz + x0, c.ipl + x0};
      const SumRow sums{sr + x0, sg + x0, sb + x0, s1 + x0, sw + x0};
      const float inv_dist = 1 / std::sqrt(float(dx * dx + dy * dy));
      if (squarings_ >= 0) moment_taps_pow2(cx, m, sums, s2 + x0, x1 - x0, inv_dist, squarings_);
      else moment_taps<-1>(cx, m, sums, s2 + x0, x1 - x0, inv_dist, o_.sigma_n);
    }
  }
  for (int x = 0; x < w; ++x) {
    const size_t i = row + size_t(x);
    const float h = history_length_[i];
    if (geometry_[i].id == kNoSurface || h >= kMinHistoryForTemporalVariance) {
      pong_[i] = ping_[i];
      continue;
    }
    const float m1 = s1[x] / sw[x], m2 = s2[x] / sw[x];
    // Falcor: the spatial estimate boosted by 4 / h in the first frames, where it is least reliable.
    pong_[i] = {Rgb(sr[x], sg[x], sb[x]) / sw[x], std::max(0.0f, m2 - m1 * m1) * 4 / std::max(h, 1.0f)};
  }
}

// Step 4, one iteration (Schied 2017 eq. 1-2): 5x5 taps of the B3 spline (1/16, 1/4, 3/8, 1/4,
// 1/16 per axis, i.e. 1, 2/3, 1/6 relative to the centre) `step` pixels apart, over planar copies
// of the data a row at a time: each tap is one branch-free loop over the row's pixels, which the
// compiler vectorises (pixels are lanes; each pixel sums its taps in the same order, so the result
// is the scalar one bit for bit). K: sigma_n = 2^K (K squarings; the default 128: 7); K < 0: pow.
template <int K>
void Svgf::atrous_row(int y, int step, const std::vector<Sample>& in, std::vector<Sample>& out) const {
  constexpr float kH[3] = {1.0f, 2.0f / 3.0f, 1.0f / 6.0f};
  const int w = width_;
  const size_t row = size_t(y) * size_t(w);
  std::vector<float> acc(size_t(w) * 8);
  float *sr = acc.data(), *sg = sr + w, *sb = sg + w, *sv = sb + w, *sw = sv + w, *ipl = sw + w, *gv = ipl + w, *gw = gv + w;
  // The variance after a 3x3 Gaussian (1/4, 1/8, 1/16) steers eq. 5's luminance weight (sec. 4.3),
  // renormalised where the 3x3 leaves the image; tap by tap over the row, as the a-trous taps.
  for (int dy = -1; dy <= 1; ++dy) {
    const int qy = y + dy;
    if (qy < 0 || qy >= height_) continue;
    for (int dx = -1; dx <= 1; ++dx) {
      const int x0 = std::max(0, -dx), x1 = std::min(w, w - dx);
      const float k = (dx == 0 ? 0.5f : 0.25f) * (dy == 0 ? 0.5f : 0.25f);
      gaussian_tap(plane_var_.data() + size_t(qy) * size_t(w) + size_t(dx + x0), gv + x0, gw + x0, x1 - x0, k);
    }
  }
  for (int x = 0; x < w; ++x) {
    ipl[x] = 1 / (o_.sigma_l * std::sqrt(std::max(gv[x] / gw[x], 0.0f)) + 1e-10f);
    sr[x] = plane_r_[row + x], sg[x] = plane_g_[row + x], sb[x] = plane_b_[row + x], sv[x] = plane_var_[row + x], sw[x] = 1;
  }
  const float *cx = plane_nx_.data() + row, *cy = plane_ny_.data() + row, *cz = plane_nz_.data() + row;
  const float *cd = plane_z_.data() + row, *cl = plane_l_.data() + row, *ipz = plane_ipz_.data() + row;
  for (int dy = -2; dy <= 2; ++dy) {
    const int qy = y + dy * step;
    if (qy < 0 || qy >= height_) continue;
    for (int dx = -2; dx <= 2; ++dx) {
      if (dx == 0 && dy == 0) continue;
      const int off = dx * step, x0 = std::max(0, -off), x1 = std::min(w, w - off);
      const size_t q = size_t(qy) * size_t(w) + size_t(off + x0);  // the tap of pixel x0 (off + x0 >= 0)
      const float *qx_ = plane_nx_.data() + q, *qy_ = plane_ny_.data() + q, *qz = plane_nz_.data() + q;
      const float *qd = plane_z_.data() + q, *ql = plane_l_.data() + q, *qv = plane_var_.data() + q;
      const float *qr = plane_r_.data() + q, *qg = plane_g_.data() + q, *qb = plane_b_.data() + q;
      const float k = kH[std::abs(dx)] * kH[std::abs(dy)];
      const float inv_dist = 1 / (float(step) * std::sqrt(float(dx * dx + dy * dy)));
      const CentreRow c{cx + x0, cy + x0, cz + x0, cd + x0, cl + x0, ipz + x0, ipl + x0};
      const TapRow t{qx_, qy_, qz, qd, ql, qv, qr, qg, qb};
      const SumRow sums{sr + x0, sg + x0, sb + x0, sv + x0, sw + x0};
      if constexpr (K >= 0)
        atrous_taps_pow2(c, t, sums, x1 - x0, k, inv_dist, K);
      else
        atrous_taps<-1>(c, t, sums, x1 - x0, k, inv_dist, o_.sigma_n);
    }
  }
  for (int x = 0; x < w; ++x) {
    const size_t i = row + size_t(x);
    out[i] = geometry_[i].id == kNoSurface ? in[i] : Sample{Rgb(sr[x], sg[x], sb[x]) / sw[x], sv[x] / (sw[x] * sw[x])};
  }
}

void Svgf::atrous(const std::vector<Sample>& in, std::vector<Sample>& out, int step) {
  for (size_t i = 0; i < in.size(); ++i) {
    plane_r_[i] = in[i].c.x, plane_g_[i] = in[i].c.y, plane_b_[i] = in[i].c.z;
    plane_var_[i] = in[i].var, plane_l_[i] = luminance(in[i].c);
  }
  parallel_for(height_, [&](int y) {
    switch (squarings_) {
      case 0: atrous_row<0>(y, step, in, out); break;
      case 1: atrous_row<1>(y, step, in, out); break;
      case 2: atrous_row<2>(y, step, in, out); break;
      case 3: atrous_row<3>(y, step, in, out); break;
      case 4: atrous_row<4>(y, step, in, out); break;
      case 5: atrous_row<5>(y, step, in, out); break;
      case 6: atrous_row<6>(y, step, in, out); break;
      case 7: atrous_row<7>(y, step, in, out); break;
      case 8: atrous_row<8>(y, step, in, out); break;
      case 9: atrous_row<9>(y, step, in, out); break;
      case 10: atrous_row<10>(y, step, in, out); break;
      default: atrous_row<-1>(y, step, in, out); break;
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
  const size_t n = noisy.size();
  for (auto* p : {&plane_nx_, &plane_ny_, &plane_nz_, &plane_z_, &plane_ipz_, &plane_r_, &plane_g_, &plane_b_, &plane_var_, &plane_l_, &plane_m2_})
    p->resize(n);
  for (size_t i = 0; i < n; ++i) {
    const Geometry& g = geometry_[i];
    plane_nx_[i] = g.n.x, plane_ny_[i] = g.n.y, plane_nz_[i] = g.n.z, plane_z_[i] = g.z;
    plane_ipz_[i] = g.id == kNoSurface ? 0.0f : 1 / (o_.sigma_z * g.dz);
  }
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
