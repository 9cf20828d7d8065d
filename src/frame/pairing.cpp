#include "frame/pairing.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace rl {

namespace {
// v wrapped into [-size/2, size/2]: the shortest way round the torus, so a tiled texture keeps
// d(partner) = -d across tile borders.
int wrap_offset(int v, int size) {
  if (v > size / 2) return v - size;
  if (v < -size / 2) return v + size;
  return v;
}

// One pass of 2x2-block permutations (grid offset by `shift` on both axes, on the torus).
void shuffle_blocks(std::vector<uint32_t>& link, int size, int shift, Pcg32& rng) {
  for (int by = 0; by < size; by += 2)
    for (int bx = 0; bx < size; bx += 2) {
      size_t cell[4];
      for (int i = 0; i < 4; ++i) {
        const int x = (bx + shift + (i & 1)) % size, y = (by + shift + (i >> 1)) % size;
        cell[i] = size_t(y) * size_t(size) + size_t(x);
      }
      for (int i = 3; i > 0; --i) {  // Fisher-Yates: a uniform permutation of the block's four links
        const int j = int(rng.next_below(uint32_t(i + 1)));
        std::swap(link[cell[i]], link[cell[j]]);
      }
    }
}
}  // namespace

PairingTexture make_pairing_texture(int size, float sigma, uint64_t seed) {
  PairingTexture tex;
  tex.size = size;
  const size_t n = size_t(size) * size_t(size);
  // Link l starts on the two horizontally adjacent texels 2l and 2l + 1 (paper fig. 3).
  std::vector<uint32_t> link(n);
  for (size_t i = 0; i < n; ++i) link[i] = uint32_t(i >> 1);
  // Each pass moves both ends of a link by about one texel per axis (variance ~1 per pass for one
  // end, so ~2 for their difference): sigma^2 / 2 passes give the link offset a standard
  // deviation of sigma (paper eq. 3, leading term; one pass gives ~0.8).
  const int passes = std::max(1, int(std::lround(double(sigma) * double(sigma) / 2.0)));
  Pcg32 rng(seed, 0x70616972u);
  for (int pass = 0; pass < passes; ++pass) shuffle_blocks(link, size, pass & 1, rng);

  std::vector<int64_t> first(n / 2, -1);
  tex.offsets.assign(2 * n, 0);
  for (size_t i = 0; i < n; ++i) {
    int64_t& other = first[link[i]];
    if (other < 0) {
      other = int64_t(i);
      continue;
    }
    const size_t j = size_t(other);
    const int dx = wrap_offset(int(i % size_t(size)) - int(j % size_t(size)), size);
    const int dy = wrap_offset(int(i / size_t(size)) - int(j / size_t(size)), size);
    tex.offsets[2 * j] = int16_t(dx), tex.offsets[2 * j + 1] = int16_t(dy);  // j -> i
    tex.offsets[2 * i] = int16_t(-dx), tex.offsets[2 * i + 1] = int16_t(-dy);  // i -> j
  }
  return tex;
}

void PairingTextures::prepare(int count, float radius) {
  if (count == count_ && radius == radius_) return;
  count_ = count, radius_ = radius;
  offsets_.clear(), first_.clear(), sizes_.clear();
  const float sigma = pairing_sigma(radius);
  // Large enough that wrapped links are rare (a link longer than W/2 would be cut short), even,
  // and different per texture: sizes without a common near-period (paper sec. 3.2, footnote 3).
  const int largest = std::max(254, 2 * int(8 * sigma));
  const int smallest = std::max(16, 2 * int(std::ceil(3 * sigma)));
  double size = largest;
  for (int t = 0; t < count; ++t, size *= 0.91) {
    const int w = std::max(smallest, 2 * int(size / 2));
    const PairingTexture tex = make_pairing_texture(w, sigma, hash_combine(uint64_t(w), uint64_t(t)));
    first_.push_back(uint32_t(offsets_.size() / 2));
    sizes_.push_back(w);
    offsets_.insert(offsets_.end(), tex.offsets.begin(), tex.offsets.end());
  }
}

}  // namespace rl
