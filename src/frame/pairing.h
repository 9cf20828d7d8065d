// Pairing textures for paired (reciprocal) spatial reuse (Lin, Kettunen, Wyman 2026, "ReSTIR PT
// Enhanced", sec. 3). Every texel of a W x W texture names one partner texel (an offset dx, dy),
// and the partner relation is an involution: the partner's partner is the texel itself. Pixel p
// then reuses from partner(p) and partner(p) reuses from p, so the two shifts the pairwise MIS
// weights of both pixels need -- T_{p->q}(X_p) and T_{q->p}(X_q) -- are each computed once, by
// their source pixel (paired_reuse.h), instead of twice.
//
// A texture is built once (make_pairing_texture): consecutive texels start as linked pairs, then
// random permutations of 2x2 blocks (the grid offset by (1, 1) every other pass, on a torus) walk
// both ends of every link, so that a link's offset becomes roughly Gaussian with a per-axis
// standard deviation of sigma after about sigma^2 / 2 passes (paper eq. 3, whose leading term this
// is). Offsets are wrapped to [-W/2, W/2] so that the texture tiles the screen and stays its own
// inverse across tile borders. Each frame and spatial round transforms every texture by one of the
// 8 symmetries of the square and an offset (paper sec. 3.2): pixel p reads texel q = M p + o (mod W)
// and its partner is p + M^T d(q). Since q' = M p' + o = q + d(q) and d(q + d(q)) = -d(q), the
// partner of the partner is p again, whatever M and o (tests/frame/test_pairing.cpp checks every
// pixel). k neighbours use k textures of different sizes, so that their periods do not line up.
#pragma once
#include <cstdint>
#include <vector>

#include "core/math.h"
#include "core/rng.h"

namespace rl {

// The partner offsets of one texture: W x W texels, (dx, dy) interleaved.
struct PairingTexture {
  int size = 0;
  std::vector<int16_t> offsets;
  int dx(int x, int y) const { return offsets[2 * (size_t(y) * size_t(size) + size_t(x))]; }
  int dy(int x, int y) const { return offsets[2 * (size_t(y) * size_t(size) + size_t(x)) + 1]; }
};

// A W x W pairing texture (W even, >= 2) whose links have a per-axis standard deviation of about
// `sigma` pixels (at least the ~0.8 of a single shuffle), from the random stream `seed`.
PairingTexture make_pairing_texture(int size, float sigma, uint64_t seed);

// The pairing's standard deviation for a spatial radius: a Gaussian whose mean distance matches
// that of a uniform disk of radius R (sigma sqrt(pi/2) = 2R/3, paper sec. 7: R = 30 gives 16).
inline float pairing_sigma(float radius) { return radius * 0.531923f; }

// One frame's transform of one texture: texel = M p + o (mod W), M = diag(sx, sy) . (swap ? P : I).
struct PairingTransform {
  bool swap = false;
  int sx = 1, sy = 1;
  int ox = 0, oy = 0;
};

// All textures of one neighbour count and radius, flat (texture t's texels start at first[t]), as
// the per-pixel stages read them.
struct PairingView {
  static constexpr int kMaxTextures = 64;
  const int16_t* offsets = nullptr;
  const uint32_t* first = nullptr;  // per texture: index of its first texel in offsets / 2
  const int32_t* sizes = nullptr;
  int count = 0;

  // Texture t's transform in spatial round `round` of (frame, seed, chain): a hash, no state.
  RESTIR_HD static PairingTransform transform(int t, int size, uint32_t frame, uint64_t seed, uint32_t chain, int round) {
    uint64_t h = hash_combine(mix64(seed ^ 0x7061697265640000ULL), frame);
    h = hash_combine(h, chain);
    h = hash_combine(h, uint64_t(round) * 64u + uint64_t(t));
    PairingTransform m;
    m.swap = h & 1u, m.sx = (h & 2u) ? -1 : 1, m.sy = (h & 4u) ? -1 : 1;
    m.ox = int((h >> 8) % uint64_t(size)), m.oy = int((h >> 32) % uint64_t(size));
    return m;
  }
  // Pixel (x, y)'s partner through texture t under transform m. transpose = false (a planted bias,
  // tests only) leaves out M^T's swap of the offset's axes: no longer an involution.
  RESTIR_HD void partner(int t, const PairingTransform& m, int x, int y, int& px, int& py, bool transpose = true) const {
    const int w = sizes[t];
    const int mx = m.sx * (m.swap ? y : x), my = m.sy * (m.swap ? x : y);  // M p
    const int qx = ((mx + m.ox) % w + w) % w, qy = ((my + m.oy) % w + w) % w;
    const size_t texel = size_t(first[t]) + size_t(qy) * size_t(w) + size_t(qx);
    const int dx = m.sx * offsets[2 * texel], dy = m.sy * offsets[2 * texel + 1];  // S d; then P: M^T = P S
    const bool swap = m.swap && transpose;
    px = x + (swap ? dy : dx), py = y + (swap ? dx : dy);
  }
};

// The textures of `count` neighbours for a spatial radius, built on the host (the sizes: the
// largest is max(254, 16 sigma), each next ~9% smaller; paper sec. 3.2 uses 254, 230, 210).
class PairingTextures {
 public:
  // Rebuilds only when count or radius changed. Throws nothing; count <= PairingView::kMaxTextures.
  void prepare(int count, float radius);
  int count() const { return count_; }
  const std::vector<int16_t>& offsets() const { return offsets_; }
  const std::vector<uint32_t>& first() const { return first_; }
  const std::vector<int32_t>& sizes() const { return sizes_; }

 private:
  int count_ = 0;
  float radius_ = -1;
  std::vector<int16_t> offsets_;
  std::vector<uint32_t> first_;
  std::vector<int32_t> sizes_;
};

}  // namespace rl
