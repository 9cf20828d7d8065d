// ReSTIR DI's frame (Bitterli et al. 2020, "Spatiotemporal reservoir resampling for real-time ray
// tracing with dynamic direct lighting"), written once for every backend (cpu_backend.h): per
// pixel sample, primary hits, this frame's light tiles, the initial candidates, temporal reuse,
// the spatial rounds and shading, each a stage over the backend's buffers. Direct lighting only
// (the reference is the path tracer at path.max_depth = 1). The math lives in restir/ and
// restir_di_pixel.h; the reuse bookkeeping in reuse_pixel.h; the stage order and random streams
// here are every backend's.
#pragma once
#include <memory>
#include <vector>

#include "frame/reservoir_chain.h"
#include "integrators/restir_di/light_tiles.h"
#include "integrators/restir_di/restir_di_pixel.h"

namespace rl {

namespace di_frame_detail {

// One chain's pre-sampled light tiles as the stages read them (LightTiles' arrays).
struct Tiles {
  const LightTileEntry* lights = nullptr;
  const EnvTileEntry* env = nullptr;
  int count = 0, size = 0, env_size = 0;
  RESTIR_HD DiTileView of(int x, int y, int width, const ReuseFrame& f) const {
    DiTileView v;
    if (count <= 0 || size <= 0) return v;  // no tiles: candidates select from every emitter
    const size_t t = light_tile_index(x, y, width, f.frame, f.seed, f.chain, count);
    v.lights = lights + t * size_t(size), v.light_count = uint32_t(size);
    if (env_size > 0) v.env = env + t * size_t(env_size), v.env_count = uint32_t(env_size);
    return v;
  }
};

// A pixel's initial reservoir: its candidates from its tile (restir_di_pixel.h).
template <class Tracer>
struct Sampler {
  FrameWorld<Tracer> fw;
  DiOptions di;
  ReuseFrame f;
  Tiles tiles;
  int width;
  RESTIR_HD DiReservoir operator()(const GSurface& s, int x, int y, uint32_t p) const {
    Pcg32 rng = make_rng(p, f.frame, RngPass::light_candidates, f.seed, f.chain);
    return di_initial_reservoir(fw.world, fw.tracer, s, di.light_candidates, di.bsdf_candidates, di.visibility_reuse, rng,
                                tiles.of(x, y, width, f));
  }
};

template <class Tracer>
struct Shader {
  FrameWorld<Tracer> fw;
  bool visibility_reuse;
  ReuseFrame f;
  const Rgb* colors;  // di.rgb_weights: the chain's per-pixel colours (null: f(Y) W_Y)
  RESTIR_HD Rgb operator()(const GSurface& s, const DiReservoir& r, uint32_t p) const {
    return di_shade(fw.world, fw.tracer, s, r, visibility_reuse, p, f.frame, f.seed, f.chain, colors ? colors + p : nullptr);
  }
};

}  // namespace di_frame_detail

template <class B>
struct RestirDiChain : ReservoirChain<B, DiReservoir> {
  typename B::Exec::template Array<LightTileEntry> tiles;
  typename B::Exec::template Array<EnvTileEntry> env_tiles;
  size_t bytes() const { return ReservoirChain<B, DiReservoir>::bytes() + array_bytes(tiles) + array_bytes(env_tiles); }
};

template <class B>
class RestirDiFrame final : public ReservoirFrame<B, RestirDiChain<B>> {
  using Base = ReservoirFrame<B, RestirDiChain<B>>;
  using Chain = RestirDiChain<B>;
  using typename Base::Exec;
  using typename Base::Tracer;
  using Base::ctx_;
  using Base::world_;

 public:
  explicit RestirDiFrame(const RenderContext& ctx) : Base(ctx) {}

  // The previous frame's BVH when the history's target includes visibility (see DiBridge).
  bool needs_previous_scene() const override {
    const DiOptions& di = ctx_.options.di;
    return scene_animated(ctx_.scene) && di.reuse.temporal && di.history_scene == HistoryScene::previous && di.visibility_reuse &&
           di.neighbor_visibility;
  }

 private:
  void render_chain(const FrameInfo& frame, const ReuseFrame& f, Chain& c) override {
    using namespace di_frame_detail;
    const DiOptions& di = ctx_.options.di;
    const FrameWorld<Tracer>& fw = this->fw();
    const Tiles tiles = light_tiles(frame, f, c);
    this->template candidates<DiReservoir>(frame, c, Sampler<Tracer>{fw, di, f, tiles, c.width}, "ReSTIR DI candidates");
    const bool planted_now = ctx_.planted && ctx_.planted->history_visibility_now;
    c.reuse(di.reuse, frame,
            DiBridges<Tracer>{fw, di.visibility_reuse, di.visibility_reuse && di.neighbor_visibility,
                              di.history_scene == HistoryScene::previous, planted_now},
            f, ctx_.planted);
    this->template shade<DiReservoir>(frame, c, Shader<Tracer>{fw, di.visibility_reuse, f, c.has_colors ? c.colors.data : nullptr},
                                      "ReSTIR DI shading");
  }

  // This frame's light tiles for chain f.chain (unless di.light_tiles = 0), drawn by a stage of the
  // backend into the chain's buffers (LightTileStage: on the device for the CUDA backend, from its
  // copy of the lights; 1 MB, plus 3.6 MB of environment directions, never copied).
  di_frame_detail::Tiles light_tiles(const FrameInfo& frame, const ReuseFrame& f, Chain& c) {
    const DiOptions& di = ctx_.options.di;
    if (!(di.light_tiles > 0 && di.light_candidates > 0)) return {};
    StageTimer timer(frame.stages, "light_tiles");
    const LightsView& lights = this->fw().world.lights;
    const LightTileShape shape = light_tile_shape(lights, di.light_tiles, di.light_tile_size, di.env_tile_size);
    if (!shape.any()) return {};
    c.tiles.reserve(size_t(shape.count) * size_t(shape.size));
    if (shape.env_size > 0) c.env_tiles.reserve(size_t(shape.count) * size_t(shape.env_size));
    EnvTileEntry* env = shape.env_size > 0 ? c.env_tiles.data : nullptr;
    const LightTileStage stage{lights, shape.size, shape.env_size, f.frame, f.seed, f.chain, c.tiles.data, env};
    Exec::for_chunks(stage.items(shape.count), kLightTileChunk, stage, "light tiles");
    return {c.tiles.data, env, shape.count, shape.size, shape.env_size};
  }
};

}  // namespace rl
