#include "integrators/restir_di/di_sampling.h"

#include <algorithm>

#include "core/parallel.h"
#include "core/widest.h"
#include "integrators/restir_di/di_candidates.h"
#include "integrators/path/path_tracer.h"

namespace rl {

// The batch of light candidates on this machine's widest vectors (core/widest.h): AVX2's 8 lanes
// where the CPU has them, the baseline SSE2's 4 elsewhere; the same floats either way.
RL_WIDEST uint32_t di_eval_light_candidates_host(const LightsView& lights, const GSurface& s, Vec3 wo_l, bool bsdf_pdfs,
                                                 DiCandidateBatch& b) {
  return di_eval_light_candidates(lights, s, wo_l, bsdf_pdfs, b);
}

Rgb di_unshadowed(const Lights& lights, const GSurface& s, const LightPoint& y, float eps, Ray* shadow_ray) {
  return di_unshadowed(lights.view(), s, y, eps, shadow_ray);
}

float di_target(const RenderContext& ctx, const GSurface& s, const LightPoint& y, bool visibility) {
  return di_target(ctx, ctx.lights, s, y, visibility);
}

float di_target(const RenderContext& ctx, const Lights& lights, const GSurface& s, const LightPoint& y, bool visibility) {
  return di_target_in(lights.view(), ctx.accel.ray_epsilon(), AccelTracer{&ctx.accel}, s, y, visibility);
}

DiReservoir di_initial_reservoir(const PathWorld& w, const RenderContext& ctx, const GSurface& s, int light_candidates, int bsdf_candidates,
                                 bool visibility, Pcg32& rng, std::span<const LightTileEntry> tile,
                                 std::span<const EnvTileEntry> env_tile) {
  const DiTileView tv{tile.data(), uint32_t(tile.size()), env_tile.data(), uint32_t(env_tile.size())};
  return di_initial_reservoir_in(w, AccelTracer{&ctx.accel}, s, light_candidates, bsdf_candidates, visibility, rng, tv);
}

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

Rgb di_specular(const RenderContext& ctx, const GSurface& s, Pcg32& rng) {
  return di_specular_in(path_world(ctx), AccelTracer{&ctx.accel}, s, rng);
}

}  // namespace rl
