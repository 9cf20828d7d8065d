// Adaptive SVGF (Schied, Peters, Dachsbacher 2018, "Gradient Estimation for Real-Time Adaptive
// Temporal Filtering", HPG 2018) over SVGF (svgf.h): the previous frame's samples, shaded again in
// this frame with their own random numbers (FrameRenderer: Integrator::reshades_previous), give a
// temporal gradient that is zero where nothing changed and noise-free where only the lighting did.
// Per frame:
//   1. one pixel q per 3x3 stratum of the previous frame (hashed per frame and stratum, sec. 4.1):
//      delta = l_reshaded(q) - l_previous(q), and the larger of the two luminances (eq. 7);
//   2. both filtered by a-trous passes over the stratum grid (3 passes, 3x3 taps, step 2^i,
//      depth- and normal-stopped as SVGF's eq. 3-4 on the strata's surfaces; sec. 4.3);
//   3. lambda = min(1, |delta| / max-luminance) (eq. 8), looked up for each pixel through its
//      motion vector, lifts SVGF's temporal weights to (1 - lambda) alpha + lambda (eq. 9).
// A prototype: pt re-renders the whole previous frame, of which 1 pixel in 9 is used (the paper
// re-shades only those); the ReSTIR integrators keep state between frames and cannot re-shade yet.
// The SVGF it wraps is the one the backend gets (denoisers.cpp): Svgf, or SvgfStages on the BVH
// backends.
#pragma once
#include <memory>
#include <vector>

#include "post/svgf.h"

namespace rl {

class Asvgf : public Denoiser {
 public:
  // Over `svgf` (null: the CPU's Svgf).
  explicit Asvgf(const DenoiseOptions& o, std::unique_ptr<SvgfFilter> svgf = nullptr)
      : o_(o), svgf_(svgf ? std::move(svgf) : std::make_unique<Svgf>(o)) {}
  bool wants_reshade() const override { return true; }
  void set_reshaded_previous(const Image& reshaded) override { reshaded_ = &reshaded; }
  void denoise(const Image& noisy, const Aovs& aovs, Image& out) override;
  // Each pixel's lambda of the last frame (0: history kept as SVGF keeps it; 1: dropped).
  const std::vector<float>& lambda() const { return lambda_; }
  const SvgfFilter& svgf() const { return *svgf_; }

 private:
  void gradients(const Aovs& aovs);

  DenoiseOptions o_;
  std::unique_ptr<SvgfFilter> svgf_;
  const Image* reshaded_ = nullptr;
  Image previous_;                        // the previous raw frame
  std::vector<float> previous_depth_, previous_dz_;
  std::vector<Vec3> previous_normal_;
  std::vector<float> lambda_;
  int frame_ = 0;
};

}  // namespace rl
