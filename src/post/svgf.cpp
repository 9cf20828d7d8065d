#include "post/svgf.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/parallel.h"
#include "core/widest.h"
#include "post/svgf_stages.h"

namespace rl {

namespace {

using namespace svgf;

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

// One tap of the a-trous pass (Schied 2017 eq. 1-2) for n pixels: the weight of eq. 3-5 times the
// B3 kernel k (svgf_stages.h's edge_weight, the per-pixel stages' function, here a vector lane per
// pixel). K: sigma_n = 2^K by K squarings; kPow: std::pow (not vectorised).
template <int K>
inline void atrous_taps(CentreRow c, TapRow q, SumRow s, int n, float k, float inv_dist, float sigma_n) {
  for (int x = 0; x < n; ++x) {
    const float wt = edge_weight<K>(c.nx[x], c.ny[x], c.nz[x], c.z[x], c.l[x], c.ipz[x], c.ipl[x], q.nx[x], q.ny[x], q.nz[x], q.z[x],
                                    q.l[x], k, inv_dist, sigma_n, K);
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

// One tap of the 7x7 moments estimate for n pixels (weights as atrous_taps with k = 1): the
// colour, the two moments and the weight summed.
struct MomentRow {
  const float *__restrict nx, *__restrict ny, *__restrict nz, *__restrict z, *__restrict l, *__restrict m1,
      *__restrict m2, *__restrict r, *__restrict g, *__restrict b;
};
template <int K>
inline void moment_taps(CentreRow c, MomentRow q, SumRow s, float* __restrict m2, int n, float inv_dist, float sigma_n) {
  for (int x = 0; x < n; ++x) {
    const float wt = edge_weight<K>(c.nx[x], c.ny[x], c.nz[x], c.z[x], c.l[x], c.ipz[x], c.ipl[x], q.nx[x], q.ny[x], q.nz[x], q.z[x],
                                    q.l[x], 1.0f, inv_dist, sigma_n, K);
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

// The previous frame's state at pixel j as svgf::reproject reads it (arrays of structs).
struct Svgf::History {
  const Geometry* geometry_;
  const Rgb* color_;
  const Vec2* moments_;
  const float* length_;
  const Geometry& geometry(size_t j) const { return geometry_[j]; }
  Rgb color(size_t j) const { return color_[j]; }
  Vec2 moments(size_t j) const { return moments_[j]; }
  float length(size_t j) const { return length_[j]; }
};

// Steps 1-2: demodulation, reprojection, temporal accumulation (Schied 2017 sec. 4.1-4.2): each
// pixel by svgf::temporal_pixel, the per-pixel stages' function.
void Svgf::demodulate_and_accumulate(const Image& noisy, const Aovs& aovs) {
  const History history{previous_geometry_.data(), history_color_.data(), history_moments_.data(), previous_length_.data()};
  const Params p = params_of(o_);
  parallel_for_pixels(width_, height_, [&](int x, int y) {
    const size_t i = aovs.index(x, y);
    demod_[i] = demodulator(aovs.albedo[i]);
    const Temporal t = temporal_pixel(previous_geometry_.empty() ? nullptr : &history, x, y, width_, height_, noisy.pixels[i],
                                      aovs.albedo[i], aovs.emission[i], aovs.motion[i], geometry_[i],
                                      lambda_.empty() ? nullptr : &lambda_[i], p);
    ping_[i] = t.s;
    moments_[i] = t.moments;
    history_length_[i] = t.length;
  });
}

// Step 3: where the history is shorter than 4 frames, the variance from the moments of a 7x7
// neighbourhood on the same surface (Schied 2017 sec. 4.2; weights as Falcor's
// SVGFFilterMoments: depth and normal as in the a-trous pass, luminance with sigma_l alone, no
// kernel), a row at a time as the a-trous passes. Skipped when every pixel has 4 frames.
void Svgf::estimate_variance() {
  bool any = false;
  for (size_t i = 0; i < ping_.size() && !any; ++i)
    any = geometry_[i].id != kNoSurface && history_length_[i] < kMinHistoryForTemporalVariance;
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
      const float inv_dist = tap_inv_distance(1, dx, dy);
      if (squarings_ >= 0) moment_taps_pow2(cx, m, sums, s2 + x0, x1 - x0, inv_dist, squarings_);
      else moment_taps<kPow>(cx, m, sums, s2 + x0, x1 - x0, inv_dist, o_.sigma_n);
    }
  }
  for (int x = 0; x < w; ++x) {
    const size_t i = row + size_t(x);
    const float h = history_length_[i];
    if (geometry_[i].id == kNoSurface || h >= kMinHistoryForTemporalVariance) {
      pong_[i] = ping_[i];
      continue;
    }
    pong_[i] = moments_result(sr[x], sg[x], sb[x], s1[x], s2[x], sw[x], h);
  }
}

// Step 4, one iteration (Schied 2017 eq. 1-2): 5x5 taps of the B3 spline (1/16, 1/4, 3/8, 1/4,
// 1/16 per axis, i.e. 1, 2/3, 1/6 relative to the centre) `step` pixels apart, over planar copies
// of the data a row at a time: each tap is one branch-free loop over the row's pixels, which the
// compiler vectorises (pixels are lanes; each pixel sums its taps in the same order, so the result
// is the scalar one bit for bit). K: sigma_n = 2^K (K squarings; the default 128: 7); K < 0: pow.
template <int K>
void Svgf::atrous_row(int y, int step, const std::vector<Sample>& in, std::vector<Sample>& out) const {
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
      const float k = gaussian_weight(dx, dy);
      gaussian_tap(plane_var_.data() + size_t(qy) * size_t(w) + size_t(dx + x0), gv + x0, gw + x0, x1 - x0, k);
    }
  }
  for (int x = 0; x < w; ++x) {
    ipl[x] = luminance_scale(o_.sigma_l, gv[x], gw[x]);
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
      const float k = b3_weight(dx, dy), inv_dist = tap_inv_distance(step, dx, dy);
      const CentreRow c{cx + x0, cy + x0, cz + x0, cd + x0, cl + x0, ipz + x0, ipl + x0};
      const TapRow t{qx_, qy_, qz, qd, ql, qv, qr, qg, qb};
      const SumRow sums{sr + x0, sg + x0, sb + x0, sv + x0, sw + x0};
      if constexpr (K >= 0)
        atrous_taps_pow2(c, t, sums, x1 - x0, k, inv_dist, K);
      else
        atrous_taps<kPow>(c, t, sums, x1 - x0, k, inv_dist, o_.sigma_n);
    }
  }
  for (int x = 0; x < w; ++x) {
    const size_t i = row + size_t(x);
    out[i] = geometry_[i].id == kNoSurface ? in[i] : atrous_result(sr[x], sg[x], sb[x], sv[x], sw[x]);
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
      default: atrous_row<kPow>(y, step, in, out); break;
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
    geometry_[i] = make_geometry(aovs.normal[i], aovs.depth[i], aovs.depth_gradient[i], aovs.surface_id[i]);
  const size_t n = noisy.size();
  for (auto* p : {&plane_nx_, &plane_ny_, &plane_nz_, &plane_z_, &plane_ipz_, &plane_r_, &plane_g_, &plane_b_, &plane_var_, &plane_l_, &plane_m2_})
    p->resize(n);
  for (size_t i = 0; i < n; ++i) {
    const Geometry& g = geometry_[i];
    plane_nx_[i] = g.n.x, plane_ny_[i] = g.n.y, plane_nz_[i] = g.n.z, plane_z_[i] = g.z;
    plane_ipz_[i] = inv_depth_scale(g, o_.sigma_z);
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
    out.pixels[i] = aovs.valid(i) ? remodulate(ping_[i].c, demod_[i], aovs.emission[i]) : noisy.pixels[i];
  std::swap(history_moments_, moments_);
  std::swap(previous_geometry_, geometry_);
}

}  // namespace rl
