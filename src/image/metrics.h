// Error metrics of a test image against a reference (converged) image, plus pixel statistics.
//
// Conventions shared by every metric:
//  - Means run over all pixels and all three channels (N = 3 * width * height), accumulated in
//    double.
//  - The images must have the same size, else std::invalid_argument with both sizes.
//  - Non-finite input is an error: if any channel of either image is NaN or +-inf, the metric
//    throws std::invalid_argument naming the image ("test"/"reference") and the first such pixel
//    (x, y) in row-major order. A silently wrong (or silently NaN) number in a study CSV is worse
//    than a failed run; call image_stats() first to count such pixels.
//  - An empty image (0 pixels) or an Image whose pixel count differs from width x height is
//    std::invalid_argument too (the mean of nothing is not 0).
#pragma once
#include <cstdint>
#include <vector>

#include "image/image.h"

namespace rl {

// MSE = (1/N) Σ (t - r)^2
double mse(const Image& test, const Image& ref);

// Relative MSE exactly as pbrt-v4 computes it: Image::MRSE in src/pbrt/util/image.cpp (used by
// `imgtool diff --metric MRSE` and `imgtool error`, which average the per-channel values):
//   relMSE = (1/N) Σ (t - r)^2 / (r + eps)^2,   eps = 0.01 in pbrt.
// Note the denominator is (r + eps)^2, not r^2 + eps (the form used e.g. by Rousselle et al. 2011
// and several ReSTIR papers); for r >> eps the two agree, near black they differ.
// Like pbrt, a term whose denominator is 0 (r == -eps) is skipped (counted as 0 but kept in N).
double rel_mse(const Image& test, const Image& ref, double eps = 0.01);
// The same over the pixels where mask != 0 only (N = 3 x their count); NaN when the mask is empty.
double rel_mse(const Image& test, const Image& ref, const std::vector<uint8_t>* mask, double eps = 0.01);

// relMSE of the block means: both images averaged over block x block tiles (the last row and column of
// tiles over the pixels they have), then rel_mse over the tile means. The part of the error that is
// spatially correlated over `block` pixels: a spatial filter of that size (a denoiser's kernel)
// averages white noise down by block^2 but leaves this part -- the "blotches" of correlated
// resampling (RTXDI's documentation: temporal-only reuse "comes out blotchy after denoising").
// block must be >= 1 (1 is rel_mse).
double rel_mse_lowpass(const Image& test, const Image& ref, int block = 8, double eps = 0.01);

// MAE = (1/N) Σ |t - r|
double mean_abs_error(const Image& test, const Image& ref);

struct ImageStats {
  double mean_luminance = 0;  // mean Rec. 709 luminance over pixels whose three channels are finite
                              // (0 if there are none)
  int nan_count = 0;          // pixels with at least one NaN channel
  int inf_count = 0;          // pixels with at least one +-inf channel (and no NaN)
  int negative_count = 0;     // finite pixels with at least one channel < 0
};
// Never throws for non-finite pixels: this is the function that finds them.
ImageStats image_stats(const Image& img);

}  // namespace rl
