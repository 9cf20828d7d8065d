#include "frame/light_tiles.h"

#include <algorithm>

#include "core/parallel.h"

namespace rl {

void LightTiles::build(const Lights& lights, int count, int size, uint32_t frame, uint64_t seed, uint32_t chain, int env_size) {
  const LightTileShape shape = light_tile_shape(lights.view(), count, size, env_size);
  count_ = shape.count, size_ = shape.size, env_size_ = shape.env_size;
  entries_.resize(size_t(count_) * size_t(size_));
  env_entries_.resize(size_t(count_) * size_t(env_size_));
  if (!shape.any()) return;
  const LightTileStage stage{lights.view(), size_, env_size_, frame, seed, chain, entries_.data(), env_entries_.data()};
  parallel_for_chunks(stage.items(count_), kLightTileChunk, stage);
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
