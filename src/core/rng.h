// Deterministic random numbers. Every stream is a hash of (pixel, frame, pass, seed), so an image
// does not depend on the thread count and random replay can regenerate a path exactly.
#pragma once
#include <cstdint>
#include <cstring>

#include "core/math.h"

namespace rl {

// 64-bit finaliser of MurmurHash3 / SplitMix64: a good avalanche for combining seeds.
RESTIR_HD inline uint64_t mix64(uint64_t v) {
  v ^= v >> 33;
  v *= 0xff51afd7ed558ccdULL;
  v ^= v >> 33;
  v *= 0xc4ceb9fe1a85ec53ULL;
  v ^= v >> 33;
  return v;
}

RESTIR_HD inline uint64_t hash_combine(uint64_t a, uint64_t b) { return mix64(a ^ (b + 0x9e3779b97f4a7c15ULL + (a << 6) + (a >> 2))); }

// A float's bits (memcpy: defined behaviour on the host and the device alike).
RESTIR_HD inline uint32_t float_bits(float f) {
  uint32_t u;
  memcpy(&u, &f, sizeof u);
  return u;
}
// A hash of a point's exact bits: equal for copies of one sample, different otherwise (in practice).
RESTIR_HD inline uint64_t hash_point(Vec3 p, uint64_t salt) {
  return hash_combine(hash_combine(hash_combine(mix64(salt), float_bits(p.x)), float_bits(p.y)), float_bits(p.z));
}

// Well-known stream identifiers ("pass" in the hash) so two uses never share random numbers.
enum class RngPass : uint32_t {
  camera = 1,
  path = 2,
  light_candidates = 3,
  temporal = 4,
  spatial = 5,
  reservoir = 6,
  misc = 7,
  light_tiles = 8,
};

// PCG32 (O'Neill 2014): small state, good statistics, cheap to seed per pixel.
struct Pcg32 {
  uint64_t state = 0x853c49e6748fea9bULL;
  uint64_t inc = 0xda3e39cb94b95bdbULL;

  Pcg32() = default;
  RESTIR_HD explicit Pcg32(uint64_t seed, uint64_t stream = 1) { seed_with(seed, stream); }
  RESTIR_HD void seed_with(uint64_t seed, uint64_t stream) {
    state = 0;
    inc = (stream << 1u) | 1u;
    next_u32();
    state += seed;
    next_u32();
  }
  RESTIR_HD uint32_t next_u32() {
    uint64_t old = state;
    state = old * 6364136223846793005ULL + inc;
    uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = uint32_t(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31));
  }
  // Uniform in [0, 1): 24 random mantissa bits, never returns 1.
  RESTIR_HD float next_float() { return float(next_u32() >> 8) * 0x1p-24f; }
  RESTIR_HD Vec2 next_2d() {
    float a = next_float();
    return {a, next_float()};
  }
  // Uniform integer in [0, n).
  RESTIR_HD uint32_t next_below(uint32_t n) { return uint32_t((uint64_t(next_u32()) * n) >> 32); }
  // Skips `delta` outputs in O(log delta) steps: the LCG's state after delta steps is
  // A state + C, with A and C composed by squaring (Brown 1994, "Random number generation with
  // arbitrary strides"; O'Neill's pcg32_advance). Lets parallel work items read one stream at their
  // own offsets, bit for bit what a sequential reader gets.
  RESTIR_HD void advance(uint64_t delta) {
    uint64_t cur_mult = 6364136223846793005ULL, cur_plus = inc, acc_mult = 1, acc_plus = 0;
    while (delta > 0) {
      if (delta & 1) acc_mult *= cur_mult, acc_plus = acc_plus * cur_mult + cur_plus;
      cur_plus = (cur_mult + 1) * cur_plus;
      cur_mult *= cur_mult;
      delta >>= 1;
    }
    state = acc_mult * state + acc_plus;
  }
};

// The canonical way to make a stream: hash of pixel, frame, pass and the user seed.
RESTIR_HD inline Pcg32 make_rng(uint32_t pixel_index, uint32_t frame, RngPass pass, uint64_t seed, uint32_t extra = 0) {
  uint64_t h = hash_combine(mix64(seed + 0x51ed270b27a3c2e1ULL), pixel_index);
  h = hash_combine(h, frame);
  h = hash_combine(h, uint64_t(pass));
  h = hash_combine(h, extra);
  return Pcg32(h, mix64(h ^ 0x2545f4914f6cdd1dULL));
}

}  // namespace rl
