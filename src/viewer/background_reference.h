// The viewer's background reference (issue 10): a progressive path-traced image of what the
// viewer shows, rendered beside it so that relMSE, FLIP, the error map and the A/B split work
// without a --reference file. It is pt with reference_options() of the viewer's options (the
// integral the viewer's unbiased integrators converge to: restir-di's is direct light), with the
// scene frozen at the viewer's animation frame, seen through the viewer's camera, one sample per
// pixel per pass, and a seed of its own: its noise is independent of the frames it is compared
// with (a correlated reference would make the error look smaller than it is). Owned and run by
// the session's worker thread.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "frame/options.h"
#include "frame/render.h"
#include "scene/scene.h"
#include "viewer/display.h"

namespace rl::viewer {

class BackgroundReference {
 public:
  // `defaults`: the options the scene file implies (apply_scene_hints), the base of the reference's
  // options. The scene must outlive this object.
  BackgroundReference(const Scene& scene, Options defaults);
  ~BackgroundReference();

  // Aims the reference at the view the viewer renders with `viewer` options through `camera` at
  // animation frame `frame`. A change of anything the reference depends on (film, path length,
  // the integrator's kind of integral, seed, camera, the animated scene's pose) restarts it and
  // returns true; ReSTIR's own options, the tone mapper and the thread count do not.
  bool aim(const Options& viewer, const CameraKey& camera, int frame);
  // Renders one more sample per pixel into the running mean and returns its wall time (ms).
  // `progress` as FrameRenderer::render_frame (it may throw to cut the pass; the mean is unchanged).
  double pass(const std::function<void(int, int)>& progress = {});

  int spp() const { return mean_.count(); }
  const Image& mean() const { return mean_.mean(); }
  // The reference's own error: an estimate of the relMSE of mean() against the image it converges
  // to, from the spread of its passes (-1 before the second pass). The metrics against it measure
  // the frames' error plus this (the two are independent), so a relMSE near it is the reference's
  // noise, not the frames' error.
  double own_rel_mse() const;
  const Options& options() const { return options_; }

 private:
  const Scene& rest_;
  Options defaults_;
  int last_key_frame_ = 0;  // animated scenes hold their pose after their last key
  std::string key_;
  Options options_;
  CameraKey camera_;
  int pose_ = -1;                  // the animation frame the reference shows (-1: a static scene)
  std::unique_ptr<Scene> frozen_;  // the animated scene at the reference's frame (null: static)
  std::unique_ptr<FrameRenderer> renderer_;
  Accumulation mean_;
  std::vector<double> squares_;  // per channel value: the running mean of the passes' squares
};

// The expected relMSE of the mean of n independent passes against their expectation, per channel
// value: the variance of the mean, (mean of squares - mean^2) / (n - 1) (the unbiased sample
// variance over n), over (mean + 0.01)^2, pbrt's relMSE denominator (image/metrics.h), averaged.
// -1 for n < 2. `squares` holds one value per channel value of `mean`.
double rel_mse_of_mean(const Image& mean, const std::vector<double>& squares, int n);

// The reference's seed for a viewer seed: a stream of its own (a fixed offset, so that the
// viewer's seed still selects the reference's noise deterministically).
uint64_t reference_seed(uint64_t viewer_seed);

// The options of one reference pass for the viewer's options: reference_options() of them, one
// sample per pixel, the reference's seed, the viewer's backend, the default thread count (the
// caller's: it does not change the image). Everything the reference depends on but the camera
// and the animation frame.
Options background_reference_options(const Options& defaults, const Options& viewer);

}  // namespace rl::viewer
