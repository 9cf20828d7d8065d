#include "integrators/pixel_sampler.h"

#include "core/sampling.h"

namespace rl {

namespace {
// D3D11 standard sample positions, x then y, 1/16 pixel units, y down.
constexpr int kMsaa1[][2] = {{0, 0}};
constexpr int kMsaa2[][2] = {{4, 4}, {-4, -4}};
constexpr int kMsaa4[][2] = {{-2, -6}, {6, -2}, {-6, 2}, {2, 6}};
constexpr int kMsaa8[][2] = {{1, -3}, {-1, 3}, {5, 1}, {-3, -5}, {-5, 5}, {-7, -1}, {3, 7}, {7, -7}};
constexpr int kMsaa16[][2] = {{1, 1},  {-1, -3}, {-3, 2}, {4, -1}, {-5, -2}, {2, 5},  {5, 3},   {3, -5},
                              {-2, 6}, {0, -7},  {-4, -6}, {-6, 4}, {-8, 0},  {7, -4}, {6, 7},   {-7, -8}};
}  // namespace

int msaa_pattern_size(int spp) {
  for (int n : {1, 2, 4, 8})
    if (spp <= n) return n;
  return 16;
}

Vec2 msaa_position(int n, int i) {
  const int(*p)[2] = n == 1 ? kMsaa1 : n == 2 ? kMsaa2 : n == 4 ? kMsaa4 : n == 8 ? kMsaa8 : kMsaa16;
  i %= n;
  return {float(p[i][0]) / 16.0f + 0.5f, float(p[i][1]) / 16.0f + 0.5f};
}

Vec2 pattern_sample(SamplePattern pattern, uint64_t index, int spp, uint64_t pixel_hash, Pcg32& rng) {
  switch (pattern) {
    case SamplePattern::center:
      return {0.5f, 0.5f};
    case SamplePattern::random:
      return rng.next_2d();
    case SamplePattern::stratified: {
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
    case SamplePattern::msaa:
      return msaa_position(msaa_pattern_size(spp), int(index % 16u));
  }
  return {0.5f, 0.5f};
}

Vec2 filter_offset(PixelFilter filter, float radius, Vec2 u, Pcg32& rng) {
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

}  // namespace rl
