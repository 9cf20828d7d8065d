// ReSTIR DI's pre-sampled light tiles, drawn each frame by a stage of the backend (LightTileStage:
// on the GPU for the CUDA backend, no host draw and no copy).
#pragma once
#include <algorithm>
#include <span>
#include <vector>

#include "core/rng.h"
#include "scene/lights.h"
#include "integrators/restir_di/di_kernel.h"

namespace rl {

// How many tiles, entries and environment directions a frame's tiles have: none without emitters,
// no environment directions without an environment.
struct LightTileShape {
  int count = 0, size = 0, env_size = 0;
  bool any() const { return count > 0 && size > 0; }
};
inline LightTileShape light_tile_shape(const LightsView& lights, int count, int size, int env_size) {
  return {lights.empty() ? 0 : std::max(count, 0), std::max(size, 0), lights.has_environment() ? std::max(env_size, 0) : 0};
}

// Draws the entries [a, b) of the tiles (LightTiles below): item i < count x (size + env_size) is
// entry i % (size + env_size) of tile i / (size + env_size). Each tile reads one random stream in
// order -- its emitters, then its environment directions (which leaves the emitter entries as they
// were without them) -- and a range skips to its first item's place in it (Pcg32::advance), so the
// tiles are the same bit for bit whatever the ranges: one item a GPU thread (Exec::for_chunks on
// the device), long runs on the host's threads, any thread count or schedule.
// entries: count x size; env: count x env_size (null if 0).
inline constexpr size_t kLightTileChunk = 1024;  // the host's runs: one stream set-up per run
struct LightTileStage {
  LightsView lights;
  int size, env_size;
  uint32_t frame;
  uint64_t seed;
  uint32_t chain;
  LightTileEntry* entries;
  EnvTileEntry* env;
  RESTIR_HD size_t items(int count) const { return size_t(count) * size_t(size + env_size); }
  RESTIR_HD void operator()(size_t a, size_t b) const {
    const size_t per_tile = size_t(size + env_size), n = size_t(size);
    while (a < b) {
      const size_t t = a / per_tile, end = b < (t + 1) * per_tile ? b : (t + 1) * per_tile;
      size_t j = a - t * per_tile;
      Pcg32 rng = make_rng(uint32_t(t), frame, RngPass::light_tiles, seed, chain);
      rng.advance(j < n ? j : n + 2 * (j - n));  // an emitter takes one number, a direction two
      for (; a < end; ++a, ++j) {
        if (j < n) {
          LightTileEntry& en = entries[t * n + j];
          en.emitter = lights.select_emitter(rng.next_float(), &en.pmf);
          continue;
        }
        LightSample ls;  // the environment samples no receiver point
        env[t * size_t(env_size) + (j - n)] = lights.sample_emitter(lights.environment_emitter(), Vec3(0), rng.next_2d(), ls)
                                                  ? EnvTileEntry{ls.wi, ls.radiance, ls.pdf}
                                                  : EnvTileEntry{};
      }
    }
  }
};

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
//
// The frames draw them with LightTileStage into the backend's memory; LightTiles draws the same
// tiles on the host, for the tests and tools that look at them.
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
  // each); light_tile_index picks a pixel's.
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
