// ReSTIR PT (Lin et al. 2022, "Generalized resampled importance sampling: foundations of ReSTIR"),
// one frame written once for every backend (cpu_backend.h): per pixel sample, a reservoir of full
// paths from the primary hit, reused from the previous frame and from neighbouring pixels through
// a shift mapping (reconnection, random replay or hybrid; see pt_path.h), then shaded with one
// path. The stages: primary hits, initial paths, temporal reuse, the spatial rounds, shading; with
// pt.direct = restir-di, ReSTIR DI on the same backend adds the emission seen and the direct light.
// The reference is the path tracer with the same path.* options (emission seen directly at the
// primary hit is added as is).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "frame/light_tiles.h"
#include "frame/reservoir_chain.h"
#include "integrators/restir_pt/restir_pt_pixel.h"

namespace rl {

namespace pt_frame_detail {

// A pixel's initial reservoir: pt.candidates walks from its primary hit (walk.h), their resampled
// NEE (pt.nee_candidates > 1) from the pixel's light tile.
template <class Tracer>
struct Sampler {
  FrameWorld<Tracer> fw;
  PathSettings ps;
  int candidates;
  ReuseFrame f;
  LightTileSet tiles;
  int width;
  RESTIR_HD PathReservoir operator()(const GSurface& s, int x, int y, uint32_t p) const {
    return initial_path_reservoir(fw.world, fw.tracer, ps, s, initial_paths_seed(f.seed, p, f.frame, f.chain), candidates,
                                  tiles.of(x, y, width, f.frame, f.seed, f.chain));
  }
};

// Emission at the primary hit (unless ReSTIR DI adds it) + f(Y) W.
struct Shader {
  bool direct_from_di;
  const Rgb* colors;  // pt.rgb_weights: the chain's per-pixel colours (null: f(Y) W_Y)
  RESTIR_HD Rgb operator()(const GSurface& s, const PathReservoir& r, uint32_t p) const {
    return pt_shade(s, r, direct_from_di, colors ? colors + p : nullptr);
  }
};

}  // namespace pt_frame_detail

// A chain's buffers, with the light tiles of resampled NEE (drawn only for pt.nee_candidates > 1).
template <class B>
struct RestirPtChain : ReservoirChain<B, PathReservoir> {
  LightTileBuffers<typename B::Exec> tiles;
  size_t bytes() const { return ReservoirChain<B, PathReservoir>::bytes() + tiles.bytes(); }
};

template <class B>
class RestirPtFrame final : public ReservoirFrame<B, RestirPtChain<B>> {
  using Base = ReservoirFrame<B, RestirPtChain<B>>;
  using Chain = RestirPtChain<B>;
  using typename Base::Exec;
  using typename Base::Tracer;
  using Base::ctx_;
  using Base::world_;

 public:
  // direct: ReSTIR DI on the same backend when pt.direct = restir-di (null otherwise). It adds only
  // to a shaded image: under a debug view it is not made, so that a view of the paths' own
  // (reconnection-depth) does not reach ReSTIR DI, which refuses it.
  RestirPtFrame(const RenderContext& ctx, std::unique_ptr<Integrator> direct)
      : Base(ctx), settings_(path_settings(ctx.options)), direct_(std::move(direct)) {
    if (ctx.planted && ctx.planted->skip_hybrid_check) settings_.check_invertibility = false;
    if (ctx.planted && ctx.planted->criterion_one_sided) settings_.retest_on_offset = false;
    if (ctx.planted && ctx.planted->forced_nee_one_sided) settings_.retest_forced_nee = false;
    if (ctx.planted && ctx.planted->roulette_in_replay) settings_.roulette_in_replay = true;
    if (ctx.planted && ctx.planted->nee_source_density) settings_.nee_source_density = true;
  }

  bool needs_previous_scene() const override {
    const Options& o = ctx_.options;
    return (scene_animated(ctx_.scene) && o.pt.reuse.temporal && o.pt.history_scene == HistoryScene::previous) ||
           (direct_ && direct_->needs_previous_scene());
  }

  void render_frame(const FrameInfo& frame, Image& out) override {
    Base::render_frame(frame, out);
    // pt.direct = restir-di: ReSTIR DI renders the emission seen and the direct light (same primary
    // rays), the paths only the indirect part (length >= 3).
    if (direct_) add_direct_light(*direct_, frame, out);
  }
  // A-SVGF: the paths and ReSTIR DI's direct light each from the history frame f-1 started from.
  void keep_history(bool on) override {
    Base::keep_history(on);
    if (direct_) direct_->keep_history(on);
  }
  size_t buffer_bytes() const override { return Base::buffer_bytes() + (direct_ ? direct_->buffer_bytes() : 0); }
  // With pt.direct = restir-di the frame is the paths' buffer plus ReSTIR DI's image, added on the host.
  FrameBuffer frame_buffer() const override { return direct_ ? FrameBuffer{} : Base::frame_buffer(); }
  void rerender_previous(const FrameInfo& previous, Image& out) override {
    Base::rerender_previous(previous, out);
    if (direct_) add_direct_light(*direct_, previous, out, /*rerender=*/true);
  }

 private:
  void render_chain(const FrameInfo& frame, const ReuseFrame& f, Chain& c) override {
    using namespace pt_frame_detail;
    const Options& o = ctx_.options;
    const FrameWorld<Tracer>& fw = this->fw();
    // Resampled NEE's light tiles (the di.light_tiles options: the same tiles ReSTIR DI's candidates read).
    const LightTileSet tiles = o.pt.nee_candidates > 1 && o.di.light_tiles > 0
                                   ? c.tiles.draw(fw.world.lights, o.di.light_tiles, o.di.light_tile_size, o.di.env_tile_size, f.frame,
                                                  f.seed, f.chain, frame.stages)
                                   : LightTileSet{};
    this->template candidates<PathReservoir>(frame, c, Sampler<Tracer>{fw, settings_, o.pt.candidates, f, tiles, c.width},
                                             "ReSTIR PT initial paths");
    const PlantedBias planted = ctx_.planted ? *ctx_.planted : PlantedBias{};
    c.reuse(o.pt.reuse, frame,
            PtBridges<Tracer>{fw, settings_, o.pt.history_scene == HistoryScene::previous, planted, ctx_.planted != nullptr}, f,
            ctx_.planted);
    this->template shade<PathReservoir>(frame, c, Shader{direct_ != nullptr, c.has_colors ? c.colors.data : nullptr}, "ReSTIR PT shading");
    if (o.render.debug_view == DebugView::reconnection_depth) {
      std::vector<PathReservoir> host(size_t(c.width) * size_t(c.height));
      Exec::download(host.data(), c.reservoirs, host.size());
      print_reconnection_histogram(frame.index, int(f.chain), host);
    }
  }

  PathSettings settings_;
  std::unique_ptr<Integrator> direct_;
};

}  // namespace rl
