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
#include "frame/light_tiles.h"
#include "integrators/restir_di/restir_di_pixel.h"

namespace rl {

namespace di_frame_detail {

// A pixel's initial reservoir: its candidates from its tile (restir_di_pixel.h).
template <class Tracer>
struct Sampler {
  FrameWorld<Tracer> fw;
  DiOptions di;
  ReuseFrame f;
  LightTileSet tiles;
  int width;
  RESTIR_HD DiReservoir operator()(const GSurface& s, int x, int y, uint32_t p) const {
    Pcg32 rng = make_rng(p, f.frame, RngPass::light_candidates, f.seed, f.chain);
    return di_initial_reservoir(fw.world, fw.tracer, s, di.light_candidates, di.bsdf_candidates, di.visibility_reuse, rng,
                                tiles.of(x, y, width, f.frame, f.seed, f.chain));
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
  LightTileBuffers<typename B::Exec> tiles;
  size_t bytes() const { return ReservoirChain<B, DiReservoir>::bytes() + tiles.bytes(); }
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
    const LightTileSet tiles = light_tiles(frame, f, c);
    this->template candidates<DiReservoir>(frame, c, Sampler<Tracer>{fw, di, f, tiles, c.width}, "ReSTIR DI candidates");
    const bool planted_now = ctx_.planted && ctx_.planted->history_visibility_now;
    c.reuse(di.reuse, frame,
            DiBridges<Tracer>{fw, di.visibility_reuse, di.visibility_reuse && di.neighbor_visibility,
                              di.history_scene == HistoryScene::previous, planted_now},
            f, ctx_.planted);
    this->template shade<DiReservoir>(frame, c, Shader<Tracer>{fw, di.visibility_reuse, f, c.has_colors ? c.colors.data : nullptr},
                                      "ReSTIR DI shading");
  }

  // This frame's light tiles for chain f.chain (unless di.light_tiles = 0).
  LightTileSet light_tiles(const FrameInfo& frame, const ReuseFrame& f, Chain& c) {
    const DiOptions& di = ctx_.options.di;
    if (!(di.light_tiles > 0 && di.light_candidates > 0)) return {};
    return c.tiles.draw(this->fw().world.lights, di.light_tiles, di.light_tile_size, di.env_tile_size, f.frame, f.seed, f.chain,
                        frame.stages);
  }
};

}  // namespace rl
