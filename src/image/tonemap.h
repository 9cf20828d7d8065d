// Display transform for PNG output: exposure -> tone-mapping operator -> [0,1] -> sRGB transfer.
// HDR files (EXR) are written linear and never pass through here.
#pragma once
#include "core/math.h"
#include "image/image.h"
#include "image/tonemap_options.h"

namespace rl {

// sRGB transfer curve, IEC 61966-2-1:1999 (piecewise: linear segment below the knee, 1/2.4 power
// above it):
//   encode(v) = 12.92 v                       for v <= 0.0031308
//             = 1.055 v^(1/2.4) - 0.055       otherwise
//   decode(e) = e / 12.92                     for e <= 0.04045
//             = ((e + 0.055) / 1.055)^2.4     otherwise
// Inputs are not clamped; negative values pass through the linear segment (encode(-v) = -encode(v)
// for small v) so encode and decode stay inverse on the whole line near 0.
float srgb_encode(float linear);
float srgb_decode(float encoded);

// One pixel through the display transform:
//   1. exposure: c * 2^o.exposure                          (stops)
//   2. negative channels are clamped to 0 (negative radiance is Monte Carlo noise, not displayable)
//   3. operator (o.tonemap), see tonemap.cpp for the formulas and citations:
//        linear            : identity
//        reinhard          : Reinhard et al. 2002 eq. 3 on luminance, L_d = L / (1 + L)
//        modified_reinhard : Reinhard et al. 2002 eq. 4 on luminance, L_d = L (1 + L / L_w^2) / (1 + L),
//                            L_w = o.white_point (maps L = L_w to exactly 1)
//        aces              : Narkowicz 2015 fit of the ACES RRT+ODT, per channel
//      The Reinhard variants scale the colour by L_d / L (hue and saturation kept).
//   4. clamp each channel to [0,1]
//   5. sRGB encode if o.srgb
// Non-finite input: NaN channels become 0, +inf becomes 1 (use image_stats() to detect them).
Rgb tonemap_pixel(Rgb linear, const OutputOptions& o);
Image tonemap(const Image& hdr, const OutputOptions& o);

}  // namespace rl
