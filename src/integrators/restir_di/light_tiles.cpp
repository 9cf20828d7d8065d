#include "integrators/restir_di/light_tiles.h"

#include <algorithm>

#include "core/parallel.h"

namespace rl {

void LightTiles::build(const Lights& lights, int count, int size, uint32_t frame, uint64_t seed, uint32_t chain, int env_size) {
  count_ = lights.empty() ? 0 : count;
  size_ = size;
  env_size_ = lights.has_environment() ? std::max(env_size, 0) : 0;
  entries_.resize(size_t(std::max(count_, 0)) * size_t(std::max(size_, 0)));
  env_entries_.resize(size_t(std::max(count_, 0)) * size_t(env_size_));
  if (count_ <= 0 || size_ <= 0) return;
  const uint32_t env = lights.environment_emitter();
  parallel_for(count_, [&](int t) {  // one stream per tile: the same tiles whatever the thread count
    Pcg32 rng = make_rng(uint32_t(t), frame, RngPass::light_tiles, seed, chain);
    for (int i = 0; i < size_; ++i) {
      LightTileEntry& en = entries_[size_t(t) * size_t(size_) + size_t(i)];
      en.emitter = lights.select_emitter(rng.next_float(), &en.pmf);
    }
    // The environment's directions, drawn after the emitters from the same stream (which leaves
    // the emitter entries as they were without them). The environment samples no receiver point.
    for (int i = 0; i < env_size_; ++i) {
      EnvTileEntry& en = env_entries_[size_t(t) * size_t(env_size_) + size_t(i)];
      LightSample ls;
      en = lights.sample_emitter(env, Vec3(0), rng.next_2d(), ls) ? EnvTileEntry{ls.wi, ls.radiance, ls.pdf} : EnvTileEntry{};
    }
  });
}

size_t LightTiles::tile_index(int x, int y, int width, uint32_t frame, uint64_t seed, uint32_t chain) const {
  return light_tile_index(x, y, width, frame, seed, chain, count_);
}

std::span<const LightTileEntry> LightTiles::tile_of(int x, int y, int width, uint32_t frame, uint64_t seed,
                                                     uint32_t chain) const {
  if (count_ <= 0 || size_ <= 0) return {};
  return {entries_.data() + tile_index(x, y, width, frame, seed, chain) * size_t(size_), size_t(size_)};
}

std::span<const EnvTileEntry> LightTiles::env_tile_of(int x, int y, int width, uint32_t frame, uint64_t seed,
                                                      uint32_t chain) const {
  if (count_ <= 0 || size_ <= 0 || env_size_ <= 0) return {};
  return {env_entries_.data() + tile_index(x, y, width, frame, seed, chain) * size_t(env_size_), size_t(env_size_)};
}

}  // namespace rl
