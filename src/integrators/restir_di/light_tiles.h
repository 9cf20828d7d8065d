// ReSTIR DI's pre-sampled light tiles, drawn on the host each frame for every backend.
#pragma once
#include <span>
#include <vector>

#include "core/rng.h"
#include "scene/lights.h"
#include "integrators/restir_di/di_kernel.h"

namespace rl {

// Pre-sampled light tiles (Wyman and Panteleev 2021, "Rearchitecting spatiotemporal resampling for
// production", §4.1; RTXDI's presampling pass): each frame, `count` tiles of `size` emitters drawn
// independently from the light selection distribution; every pixel of a 16x16-pixel block draws
// its light candidates' emitters uniformly from one tile, so they come from a few kilobytes that
// stay in cache instead of from the whole light list. Each entry, hence each candidate, is
// marginally distributed by the selection pmf, so the candidates' source pdf is unchanged and the
// estimator stays unbiased: the resampling weights need only each candidate's marginal density,
// and correlated candidates are allowed (Lin et al. 2022, GRIS §4, the unbiasedness of
// E[f(Y) W] = sum_i E[m_i(X_i) f(X_i) / p_i(X_i)] uses linearity of expectation only).
// Each tile also holds `env_size` directions drawn from the environment map's importance
// distribution (RTXDI's environment presampling, ibid.): a candidate whose emitter is the
// environment takes one of them uniformly instead of sampling the map itself -- a random texel of a
// large image and two table lookups, the cache misses that dominated env-lit frames. Each entry is
// marginally distributed by the environment's density, so the same argument keeps it unbiased.
class LightTiles {
 public:
  // Draws the tiles of one frame (count 0: no tiles, candidates select from the whole list).
  void build(const Lights& lights, int count, int size, uint32_t frame, uint64_t seed, uint32_t chain, int env_size = 0);
  // The tile of pixel (x, y), chosen at random per 16x16-pixel block and frame; empty without tiles.
  std::span<const LightTileEntry> tile_of(int x, int y, int width, uint32_t frame, uint64_t seed, uint32_t chain) const;
  // The same tile's environment directions; empty without tiles, environment or env_size.
  std::span<const EnvTileEntry> env_tile_of(int x, int y, int width, uint32_t frame, uint64_t seed, uint32_t chain) const;
  static constexpr int kBlockPixels = kLightTileBlockPixels;
  // The tiles as flat arrays (count() tiles of size() entries, env_size() environment directions
  // each), for the CUDA backend's copy; light_tile_index picks a pixel's.
  int count() const { return count_; }
  int size() const { return size_; }
  int env_size() const { return env_size_; }
  const std::vector<LightTileEntry>& entries() const { return entries_; }
  const std::vector<EnvTileEntry>& env_entries() const { return env_entries_; }

 private:
  size_t tile_index(int x, int y, int width, uint32_t frame, uint64_t seed, uint32_t chain) const;
  int count_ = 0, size_ = 0, env_size_ = 0;
  std::vector<LightTileEntry> entries_;
  std::vector<EnvTileEntry> env_entries_;
};

}  // namespace rl
