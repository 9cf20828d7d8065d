// Pre-sampled light tiles (Wyman and Panteleev 2021; RTXDI), shared by the algorithms whose light
// candidates come from them: ReSTIR DI's initial candidates and ReSTIR PT's resampled next-event
// estimation (pt.nee_candidates > 1). Drawn each frame by a stage of the backend (LightTileStage: on
// the GPU for the CUDA backend, no host draw and no copy) into a chain's LightTileBuffers.
#pragma once
#include <algorithm>
#include <span>
#include <vector>

#include "core/rng.h"
#include "frame/integrator.h"
#include "frame/stage_times.h"
#include "scene/lights.h"

namespace rl {

// One pre-selected emitter of a light tile and its selection probability.
struct LightTileEntry {
  uint32_t emitter = kNoEmitter;
  float pmf = 0;
};

// One presampled direction of the environment map and what its sampling computed: the radiance
// arriving from it and its solid-angle density (without the environment's selection pmf).
struct EnvTileEntry {
  Vec3 direction;
  Rgb radiance{0};
  float pdf = 0;
};

// The tile that pixel (x, y) takes its candidates from (LightTiles): drawn per 16x16-pixel block,
// frame and chain from its own stream, so every pixel of a block reads the same `count` entries.
inline constexpr int kLightTileBlockPixels = 16;
RESTIR_HD inline uint32_t light_tile_index(int x, int y, int width, uint32_t frame, uint64_t seed, uint32_t chain, int count) {
  const int blocks_x = (width + kLightTileBlockPixels - 1) / kLightTileBlockPixels;
  const uint32_t block = uint32_t((y / kLightTileBlockPixels) * blocks_x + x / kLightTileBlockPixels);
  Pcg32 rng = make_rng(block, frame, RngPass::light_tiles, seed, chain + 0x9e3779b9u);
  const uint32_t last = uint32_t(count) - 1, i = uint32_t(rng.next_float() * float(count));
  return i < last ? i : last;
}

// A pixel's pre-sampled light tile as the candidates read it: null entries, no tile.
struct LightTileView {
  const LightTileEntry* lights = nullptr;
  uint32_t light_count = 0;
  const EnvTileEntry* env = nullptr;
  uint32_t env_count = 0;
  // An entry's index for uniform u (the last one for u rounding up to 1).
  RESTIR_HD static uint32_t pick(float u, uint32_t count) {
    const uint32_t i = uint32_t(u * float(count));
    return i < count - 1 ? i : count - 1;
  }
};

// One frame's tiles of a chain as the stages read them (LightTileBuffers::draw).
struct LightTileSet {
  const LightTileEntry* lights = nullptr;
  const EnvTileEntry* env = nullptr;
  int count = 0, size = 0, env_size = 0;
  // Pixel (x, y)'s tile in this frame and chain; empty without tiles (candidates select from every emitter).
  RESTIR_HD LightTileView of(int x, int y, int width, uint32_t frame, uint64_t seed, uint32_t chain) const {
    LightTileView v;
    if (count <= 0 || size <= 0) return v;
    const size_t t = light_tile_index(x, y, width, frame, seed, chain, count);
    v.lights = lights + t * size_t(size), v.light_count = uint32_t(size);
    if (env_size > 0) v.env = env + t * size_t(env_size), v.env_count = uint32_t(env_size);
    return v;
  }
};

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

// A chain's tile buffers in the backend's memory (1 MB at the defaults, plus 3.6 MB of environment
// directions), drawn by LightTileStage on the backend each frame (never copied).
template <class Exec>
struct LightTileBuffers {
  typename Exec::template Array<LightTileEntry> entries;
  typename Exec::template Array<EnvTileEntry> env;
  size_t bytes() const { return array_bytes(entries) + array_bytes(env); }
  // This frame's tiles for `chain` (count tiles of size emitters and env_size environment
  // directions; none without emitters or with count 0), timed as the stage "light_tiles".
  LightTileSet draw(const LightsView& lights, int count, int size, int env_size, uint32_t frame, uint64_t seed, uint32_t chain,
                    StageTimes* stages) {
    StageTimer timer(stages, "light_tiles");
    const LightTileShape shape = light_tile_shape(lights, count, size, env_size);
    if (!shape.any()) return {};
    entries.reserve(size_t(shape.count) * size_t(shape.size));
    if (shape.env_size > 0) env.reserve(size_t(shape.count) * size_t(shape.env_size));
    EnvTileEntry* env_data = shape.env_size > 0 ? env.data : nullptr;
    const LightTileStage stage{lights, shape.size, shape.env_size, frame, seed, chain, entries.data, env_data};
    Exec::for_chunks(stage.items(shape.count), kLightTileChunk, stage, "light tiles");
    return {entries.data, env_data, shape.count, shape.size, shape.env_size};
  }
};

}  // namespace rl
