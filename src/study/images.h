// Per-configuration images of a study: EXR + tone-mapped PNG, an error map PNG (FLIP map where
// image/flip.h is built in, else the relative error), zoomed crops for the report, and the metrics
// that compare an image with its reference.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "image/image.h"
#include "frame/options.h"

namespace rl::study {

// Mean LDR-FLIP of the tone-mapped images (o = the configuration's output options), or NaN when
// no FLIP implementation is compiled in.
double flip_metric(const Image& test, const Image& ref, const OutputOptions& o);
// The same over the pixels where mask != 0 (NaN when the mask is empty).
double flip_metric(const Image& test, const Image& ref, const OutputOptions& o, const std::vector<uint8_t>& mask);
bool flip_available();

// Error map as a colour-mapped LDR image (black -> red -> yellow -> white): FLIP of the tone-mapped
// images, else min(1, |t - r| / (r + 0.01)) on luminance.
Image error_map(const Image& test, const Image& ref, const OutputOptions& o);

// The colour scale of error_map(): a bar `width` pixels wide running from 0 (left) to 1 (right)
// through the very colours error_map() uses, with tick marks and labels at 0, 0.25, 0.5, 0.75 and 1
// below it (drawn with stb_easy_font), on a white background.
Image error_scale_bar(int width = 280);

// The region zoom_crop() shows: the centre quarter of a width x height image, at least 8x8 pixels.
struct CropRect {
  int x0 = 0, y0 = 0, width = 0, height = 0;
};
CropRect crop_rect(int width, int height);

// crop_rect() of the image, scaled up by an integer factor (nearest neighbour).
Image zoom_crop(const Image& ldr, int scale = 4);

// Per-pixel standard deviation across images (same size, >= 2), mean over pixels and channels.
double noise_across(const std::vector<Image>& images);

// Writes PREFIX.exr, PREFIX.png, PREFIX-crop.png (and with ref: PREFIX-error.png, PREFIX-error-crop.png).
void write_config_images(const std::string& prefix, const Image& img, const Image* ref, const OutputOptions& o,
                         bool exr = true);

}  // namespace rl::study
