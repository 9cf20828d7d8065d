#include "post/asvgf.h"

#include <algorithm>
#include <cmath>

#include "core/parallel.h"
#include "core/rng.h"

namespace rl {

namespace {

constexpr int kStratum = 3;              // Schied 2018: one re-shaded sample per 3x3 pixels
constexpr int kGradientIterations = 3;   // a-trous passes over the stratum grid (our choice)

// One stratum's gradient sample: its pixel's surface and the two sums a-trous filters.
struct Gradient {
  float delta = 0, norm = 0;  // l_new - l_old, max(l_new, l_old)
  float z = 0, dz = 0;
  Vec3 n;
  bool valid = false;
};

// One a-trous pass over the stratum grid (3x3 taps, step `step` strata): eq. 3-4 weights between
// the strata's surfaces; the delta and the norm filtered alike (Schied 2018 sec. 4.3).
void filter_gradients(const std::vector<Gradient>& in, std::vector<Gradient>& out, int gw, int gh, int step,
                      const DenoiseOptions& o) {
  parallel_for(gh, [&](int y) {
    for (int x = 0; x < gw; ++x) {
      const Gradient& c = in[size_t(y) * size_t(gw) + size_t(x)];
      Gradient r = c;
      if (!c.valid) {
        out[size_t(y) * size_t(gw) + size_t(x)] = r;
        continue;
      }
      float sw = 0, sd = 0, sn = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int qx = x + dx * step, qy = y + dy * step;
          if (qx < 0 || qy < 0 || qx >= gw || qy >= gh) continue;
          const Gradient& q = in[size_t(qy) * size_t(gw) + size_t(qx)];
          if (!q.valid) continue;
          const float nd = std::max(0.0f, dot(c.n, q.n));
          const float dist = float(step * kStratum) * std::sqrt(float(dx * dx + dy * dy));
          const float wz = dist > 0 ? std::fabs(c.z - q.z) / (o.sigma_z * c.dz * dist) : 0.0f;
          const float w = (dx == 0 ? 1.0f : 0.5f) * (dy == 0 ? 1.0f : 0.5f) * std::pow(nd, o.sigma_n) * std::exp(-wz);
          sw += w, sd += w * q.delta, sn += w * q.norm;
        }
      r.delta = sd / sw, r.norm = sn / sw;
      out[size_t(y) * size_t(gw) + size_t(x)] = r;
    }
  });
}

}  // namespace

void Asvgf::gradients(const Aovs& aovs) {
  const int w = aovs.width, h = aovs.height, gw = (w + kStratum - 1) / kStratum, gh = (h + kStratum - 1) / kStratum;
  std::vector<Gradient> g(size_t(gw) * size_t(gh)), tmp(g.size());
  for (int sy = 0; sy < gh; ++sy)
    for (int sx = 0; sx < gw; ++sx) {
      // The stratum's sample: a pixel hashed from the stratum and the frame (sec. 4.1).
      const uint64_t hsh = mix64(hash_combine(uint64_t(frame_), uint64_t(sy) * uint64_t(gw) + uint64_t(sx)));
      const int qx = std::min(w - 1, sx * kStratum + int(hsh % kStratum)), qy = std::min(h - 1, sy * kStratum + int((hsh >> 8) % kStratum));
      const size_t q = size_t(qy) * size_t(w) + size_t(qx);
      Gradient& s = g[size_t(sy) * size_t(gw) + size_t(sx)];
      const float lo = luminance(previous_.pixels[q]), ln = luminance(reshaded_->pixels[q]);
      s = {ln - lo, std::max(lo, ln), previous_depth_[q], previous_dz_[q], previous_normal_[q], previous_depth_[q] > 0};
    }
  for (int it = 0; it < kGradientIterations; ++it) {
    filter_gradients(g, tmp, gw, gh, 1 << it, o_);
    std::swap(g, tmp);
  }
  // Each pixel's lambda (eq. 8) from the stratum its history comes from (its motion vector).
  lambda_.assign(size_t(w) * size_t(h), 0.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      const int px = int(std::floor(float(x) + 0.5f + aovs.motion[i].x)), py = int(std::floor(float(y) + 0.5f + aovs.motion[i].y));
      if (px < 0 || py < 0 || px >= w || py >= h) continue;
      const Gradient& s = g[size_t(py / kStratum) * size_t(gw) + size_t(px / kStratum)];
      if (s.valid && s.norm > 0) lambda_[i] = std::min(1.0f, std::fabs(s.delta) / s.norm);
    }
}

void Asvgf::denoise(const Image& noisy, const Aovs& aovs, Image& out) {
  const bool history = reshaded_ && previous_.width == noisy.width && previous_.height == noisy.height &&
                       reshaded_->width == noisy.width && reshaded_->height == noisy.height;
  if (history) gradients(aovs);
  else lambda_.clear();
  svgf_->set_temporal_lambda(lambda_);
  svgf_->denoise(noisy, aovs, out);
  previous_ = noisy;
  previous_depth_ = aovs.depth;
  previous_normal_ = aovs.normal;
  previous_dz_.resize(aovs.depth.size());
  for (size_t i = 0; i < previous_dz_.size(); ++i) previous_dz_[i] = std::max(aovs.depth_gradient[i], 1e-4f * aovs.depth[i]);
  reshaded_ = nullptr;
  ++frame_;
}

}  // namespace rl
