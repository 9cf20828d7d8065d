// Primary-ray positions inside a pixel (thesis §4.1.2, "sample pattern") and the pixel filter,
// applied by filter importance sampling (pbrt-v4 FilterSampler): the offset is drawn from the
// filter's shape, so every sample has weight 1 for the positive filters offered here.
#pragma once
#include <cstdint>

#include "core/rng.h"
#include "integrators/options.h"

namespace rl {

// Point in [0,1)^2 for sample `index` of a pixel. `index` counts over the whole sequence
// (frame * spp + sample), so patterns continue across frames; `spp` is samples per frame.
// pixel_hash decorrelates pixels (Cranley-Patterson rotation for Halton).
Vec2 pattern_sample(SamplePattern pattern, uint64_t index, int spp, uint64_t pixel_hash, Pcg32& rng);

// Offset from the pixel centre in pixels, drawn from the filter given u in [0,1)^2.
Vec2 filter_offset(PixelFilter filter, float radius, Vec2 u, Pcg32& rng);

// The Direct3D standard multisample positions (D3D11_STANDARD_MULTISAMPLE_PATTERN) for 1, 2, 4, 8
// and 16 samples, in 1/16 pixel units from the centre. Counts in between use the next larger
// pattern; larger spp cycle through the 16-sample pattern.
int msaa_pattern_size(int spp);
Vec2 msaa_position(int pattern_size, int i);

}  // namespace rl
