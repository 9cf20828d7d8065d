// Primary-ray positions inside a pixel (thesis §4.1.2, "sample pattern") and the pixel filter,
// applied by filter importance sampling (pbrt-v4 FilterSampler): the offset is drawn from the
// filter's shape, so every sample has weight 1 for the positive filters offered here.
#pragma once
#include <cstdint>

#include "core/rng.h"
#include "core/sampling.h"
#include "frame/options.h"
#include "scene/camera.h"

namespace rl {

// Point in [0,1)^2 for sample `index` of a pixel (pattern_sample): `index` counts over the whole
// sequence (frame * spp + sample), so patterns continue across frames; `spp` is samples per frame.
// A pattern is anti-aliasing over frames (the thesis' sect. 4.1.2; a real-time renderer's camera
// jitter, e.g. Falcor's DxSamplePattern and StratifiedSamplePattern): at a few samples per frame the
// positions cycle over frames instead of repeating every frame. msaa cycles through the D3D 8x
// pattern (16x from 9 spp per frame); stratified, at 1, 2, 4 or 8 spp per frame, through the 16
// strata of a 4x4 grid in Bayer order (consecutive samples land far apart, so each frame's samples
// are spread and 16 / spp frames cover every stratum once), else one grid per frame.
// pixel_hash decorrelates pixels (Cranley-Patterson rotation for Halton).
// filter_offset: offset from the pixel centre in pixels, drawn from the filter given u in [0,1)^2.
// msaa_position: the Direct3D standard multisample positions (D3D11_STANDARD_MULTISAMPLE_PATTERN)
// for 1, 2, 4, 8 and 16 samples, in 1/16 pixel units from the centre. Counts in between use the
// next larger pattern (msaa_pattern_size); larger spp cycle through the 16-sample pattern.
RESTIR_HD inline int msaa_pattern_size(int spp) { return spp <= 1 ? 1 : spp <= 2 ? 2 : spp <= 4 ? 4 : spp <= 8 ? 8 : 16; }

RESTIR_HD inline Vec2 msaa_position(int n, int i) {
  // D3D11 standard sample positions, x then y, 1/16 pixel units, y down; the patterns of 1, 2, 4
  // and 8 samples follow each other in one table (local: device code sees no host globals).
  const signed char table[][2] = {{0, 0},                                                                   // 1
                                  {4, 4},   {-4, -4},                                                       // 2
                                  {-2, -6}, {6, -2},  {-6, 2},  {2, 6},                                     // 4
                                  {1, -3},  {-1, 3},  {5, 1},   {-3, -5}, {-5, 5}, {-7, -1}, {3, 7}, {7, -7},  // 8
                                  {1, 1},   {-1, -3}, {-3, 2},  {4, -1},  {-5, -2}, {2, 5},  {5, 3},  {3, -5},  // 16
                                  {-2, 6},  {0, -7},  {-4, -6}, {-6, 4},  {-8, 0},  {7, -4}, {6, 7},  {-7, -8}};
  const int first = n == 1 ? 0 : n == 2 ? 1 : n == 4 ? 3 : n == 8 ? 7 : 15;
  i %= n;
  return {float(table[first + i][0]) / 16.0f + 0.5f, float(table[first + i][1]) / 16.0f + 0.5f};
}

RESTIR_HD inline Vec2 pattern_sample(SamplePattern pattern, uint64_t index, int spp, uint64_t pixel_hash, Pcg32& rng) {
  switch (pattern) {
    case SamplePattern::center:
      return {0.5f, 0.5f};
    case SamplePattern::random:
      return rng.next_2d();
    case SamplePattern::stratified: {
      if (16 % spp == 0) {
        // The 4x4 grid over the sequence: rank r = index mod 16 takes the cell whose 4x4 Bayer
        // matrix entry is r (ranks 0-3 fall in the four quadrants, 0-7 in every other column ...).
        const unsigned char cell_of_rank[16] = {0, 10, 2, 8, 5, 15, 7, 13, 1, 11, 3, 9, 4, 14, 6, 12};
        const int cell = cell_of_rank[index % 16u];
        Vec2 j = rng.next_2d();
        return {(float(cell % 4) + j.x) / 4.0f, (float(cell / 4) + j.y) / 4.0f};
      }
      // Jittered grid of nx x ny strata per frame; sample s of a frame takes stratum s.
      int nx = int(std::ceil(std::sqrt(float(spp))));
      int ny = (spp + nx - 1) / nx;
      int s = int(index % uint64_t(spp));
      int cx = s % nx, cy = s / nx;
      Vec2 j = rng.next_2d();
      return {(float(cx) + j.x) / float(nx), (float(cy) + j.y) / float(ny)};
    }
    case SamplePattern::halton: {
      // Halton (2,3) with a per-pixel Cranley-Patterson rotation so pixels are decorrelated.
      float rx = float(uint32_t(pixel_hash) >> 8) * 0x1p-24f, ry = float(uint32_t(pixel_hash >> 32) >> 8) * 0x1p-24f;
      float x = radical_inverse(0, index + 1) + rx, y = radical_inverse(1, index + 1) + ry;
      x -= std::floor(x);
      y -= std::floor(y);
      return {std::min(x, 0x1.fffffep-1f), std::min(y, 0x1.fffffep-1f)};
    }
    case SamplePattern::msaa: {
      const int n = msaa_pattern_size(spp < 8 ? 8 : spp);
      return msaa_position(n, int(index % uint64_t(n)));
    }
  }
  return {0.5f, 0.5f};
}

// Whether pattern_sample or filter_offset draws from its stream (camera_ray seeds one only then).
RESTIR_HD inline bool sampling_uses_rng(SamplePattern pattern, PixelFilter filter) {
  return pattern == SamplePattern::random || pattern == SamplePattern::stratified || filter == PixelFilter::gaussian;
}

RESTIR_HD inline Vec2 filter_offset(PixelFilter filter, float radius, Vec2 u, Pcg32& rng) {
  switch (filter) {
    case PixelFilter::box:
      return {(2 * u.x - 1) * radius, (2 * u.y - 1) * radius};
    case PixelFilter::triangle:
      return {sample_tent(u.x, radius), sample_tent(u.y, radius)};
    case PixelFilter::gaussian: {
      // Truncated Gaussian with sigma = radius / 3 (the pattern point picks a start; rejection
      // sampling with the pixel's own stream keeps it exact). Radius 0 degenerates to the centre.
      if (radius <= 0) return {0, 0};
      float sigma = radius / 3;
      Vec2 v = u;
      for (int tries = 0; tries < 64; ++tries) {
        float r = std::sqrt(-2 * std::log(std::max(1 - v.x, 1e-12f))), phi = 2 * kPi * v.y;
        Vec2 o{r * std::cos(phi) * sigma, r * std::sin(phi) * sigma};
        if (std::fabs(o.x) <= radius && std::fabs(o.y) <= radius) return o;
        v = rng.next_2d();
      }
      return {0, 0};
    }
  }
  return {0, 0};
}

// The options a camera ray depends on (a plain copy of the render options' fields).
struct CameraSampling {
  uint64_t seed = 0;
  int spp = 1;
  SamplePattern pattern = SamplePattern::halton;
  PixelFilter filter = PixelFilter::box;
  float filter_radius = 0.5f;
};
inline CameraSampling camera_sampling(const Options& o) {
  return {o.render.seed, o.render.spp, o.render.sample_pattern, o.film.filter, o.film.filter_radius};
}

// Primary ray for sample `sample` of pixel (x, y) in frame `frame`: sample pattern + pixel filter.
RESTIR_HD inline Ray camera_ray(const CameraSampling& cs, const PerspectiveCamera& camera, int x, int y, int frame, int sample) {
  const uint32_t pixel = uint32_t(y) * uint32_t(camera.width()) + uint32_t(x);
  // The stream and the pixel hash only where the pattern or filter reads them: seeding a stream
  // hashes six times, and the default Halton pattern with a box filter reads none of it (issue 9).
  Pcg32 rng;
  if (sampling_uses_rng(cs.pattern, cs.filter))
    rng = make_rng(pixel, uint32_t(frame), RngPass::camera, cs.seed, uint32_t(sample));
  const uint64_t pixel_hash = cs.pattern == SamplePattern::halton ? mix64(hash_combine(cs.seed, pixel)) : 0;
  const Vec2 u = pattern_sample(cs.pattern, uint64_t(frame) * uint64_t(cs.spp) + uint64_t(sample), cs.spp, pixel_hash, rng);
  const Vec2 o = filter_offset(cs.filter, cs.filter_radius, u, rng);
  return camera.generate_ray({float(x) + 0.5f + o.x, float(y) + 0.5f + o.y});
}

}  // namespace rl
