// Spatiotemporal Variance-Guided Filtering (Schied et al. 2017, "Spatiotemporal Variance-Guided
// Filtering: Real-Time Reconstruction for Path-Traced Global Illumination", HPG 2017) over a
// finished frame and its AOVs (frame/aov.h), after any integrator. Per frame:
//   1. demodulate: illumination = (radiance - emission) / albedo (sec. 4, "albedo demodulation");
//   2. reproject through the motion vectors (bilinear 2x2, each tap tested for the same surface id,
//      a close depth and normal; Falcor's SVGF) and blend colour and luminance moments (l, l^2)
//      into the history with alpha = max(alpha, 1 / history length) (sec. 4.1, 4.2);
//   3. variance = m2 - m1^2; where history < 4 frames, a 7x7 edge-aware spatial estimate (sec. 4.2);
//   4. a-trous wavelet iterations (5x5 B3-spline taps, step 2^i) with the depth, normal and
//      luminance edge-stopping functions of eq. 3-5 (luminance: variance after a 3x3 Gaussian),
//      the variance filtered with the squared weights (eq. 2); the first iteration's output is
//      the next frame's colour history (sec. 4.3);
//   5. re-modulate: radiance = illumination x albedo + emission.
// Pixels without a surface (the environment) pass through unchanged. Every pixel is computed from
// fixed inputs in a fixed order: the result does not depend on the thread count. The per-pixel math
// is svgf_stages.h's, shared with the per-pixel stages of the BVH backends (svgf_driver.h), which
// give the same floats.
#pragma once
#include <cmath>
#include <vector>

#include "frame/denoiser.h"
#include "post/svgf_stages.h"

namespace rl {

// What A-SVGF (asvgf.h) needs of an SVGF: Svgf here, SvgfStages<Exec> (svgf_driver.h) on the
// BVH backends (make_denoiser picks by render.backend).
class SvgfFilter : public Denoiser {
 public:
  // Each pixel's history length after the last frame, in frames including it (1 = history
  // dropped or first frame): what tests read to see reprojection keep or reject history.
  virtual const std::vector<float>& history_length() const = 0;
  // A-SVGF (src/post/asvgf.h): per pixel, lambda in [0, 1] lifts the next frame's temporal
  // weights to (1 - lambda) alpha + lambda (Schied et al. 2018, eq. 9); empty: none.
  virtual void set_temporal_lambda(std::vector<float> lambda) = 0;
};

// The CPU backend's SVGF: the filter a row at a time, vectorised.
class Svgf : public SvgfFilter {
 public:
  explicit Svgf(const DenoiseOptions& o)
      : o_(o), squarings_(svgf::squarings_of(o.sigma_n)) {}
  void denoise(const Image& noisy, const Aovs& aovs, Image& out) override;
  const std::vector<float>& history_length() const override { return history_length_; }
  void set_temporal_lambda(std::vector<float> lambda) override { lambda_ = std::move(lambda); }

  using Sample = svgf::Sample;      // demodulated illumination and its variance
  using Geometry = svgf::Geometry;  // the frame's geometry as the edge-stopping functions read it

 private:
  struct History;
  void demodulate_and_accumulate(const Image& noisy, const Aovs& aovs);
  void estimate_variance();
  void moments_row(int y);
  void atrous(const std::vector<Sample>& in, std::vector<Sample>& out, int step);
  template <int K>
  void atrous_row(int y, int step, const std::vector<Sample>& in, std::vector<Sample>& out) const;

  DenoiseOptions o_;
  int squarings_;  // sigma_n = 2^squarings_ (the normal weight by squaring), else -1: std::pow
  // Planar copies for the vectorised a-trous rows: geometry once a frame (ipz = 1 / (sigma_z dz),
  // 0 without a surface), colour, variance and luminance once a pass.
  std::vector<float> plane_nx_, plane_ny_, plane_nz_, plane_z_, plane_ipz_, plane_r_, plane_g_, plane_b_, plane_var_, plane_l_,
      plane_m2_;
  int width_ = 0, height_ = 0;
  std::vector<Geometry> geometry_, previous_geometry_;
  std::vector<Rgb> demod_;  // per pixel: what radiance was divided by (albedo, 1 where a channel is ~0)
  std::vector<Rgb> history_color_;           // previous frame's first a-trous output (feedback)
  std::vector<Vec2> history_moments_, moments_;
  std::vector<float> history_length_, previous_length_;
  std::vector<Sample> ping_, pong_;
  std::vector<float> lambda_;
};

}  // namespace rl
