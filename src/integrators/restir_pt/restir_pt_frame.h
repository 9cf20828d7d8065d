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

#include "frame/reservoir_chain.h"
#include "integrators/restir_pt/restir_pt_pixel.h"

namespace rl {

namespace pt_frame_detail {

template <class Tracer>
struct CandidateStage {
  FrameWorld<Tracer> fw;
  PathSettings ps;
  int candidates;
  ReuseFrame f;
  GBufferView g;
  PathReservoir* out;
  RESTIR_HD void operator()(int x, int y) const {
    const uint32_t p = uint32_t(y * g.width + x);
    const uint64_t path_seed = initial_paths_seed(f.seed, p, f.frame, f.chain);
    out[p] = initial_path_reservoir(fw.world, fw.tracer, ps, g.at(x, y), path_seed, candidates);
  }
};

// Emission at the primary hit (unless ReSTIR DI adds it) + f(Y) W, or a debug view.
struct ShadeStage {
  GBufferView g;
  const PathReservoir* reservoirs;
  bool direct_from_di;
  DebugView view;
  ReuseDebugView dbg;
  Rgb* sum;
  RESTIR_HD void operator()(int x, int y) const {
    const uint32_t p = uint32_t(y * g.width + x);
    const PathReservoir& r = reservoirs[p];
    if (add_debug_view(view, r, dbg, p, sum, r.has_sample() ? r.sample.rc : 0)) return;
    sum[p] += pt_shade(g.at(x, y), r, direct_from_di);
  }
};

}  // namespace pt_frame_detail

template <class B>
class RestirPtFrame final : public Integrator {
 public:
  using Exec = typename B::Exec;
  using Tracer = typename B::Tracer;

  // direct: ReSTIR DI on the same backend when pt.direct = restir-di (null otherwise). It adds only
  // to a shaded image: under a debug view it is not made, so that a view of the paths' own
  // (reconnection-depth) does not reach ReSTIR DI, which refuses it.
  RestirPtFrame(const RenderContext& ctx, std::unique_ptr<Integrator> direct)
      : ctx_(ctx), settings_(path_settings(ctx.options)), direct_(std::move(direct)) {
    if (ctx.planted && ctx.planted->skip_hybrid_check) settings_.check_invertibility = false;
  }

  bool needs_previous_scene() const override {
    const Options& o = ctx_.options;
    return (scene_animated(ctx_.scene) && o.pt.reuse.temporal && o.pt.history_scene == HistoryScene::previous) ||
           (direct_ && direct_->needs_previous_scene());
  }

  void render_frame(const FrameInfo& frame, Image& out) override {
    world_.update(ctx_, frame);
    render_chains<Exec>(chains_, ctx_.options.render.spp, sum_, out, [&](int s, Chain& c) { render_chain(frame, s, c); });
    // pt.direct = restir-di: ReSTIR DI renders the emission seen and the direct light (same primary
    // rays), the paths only the indirect part (length >= 3).
    if (direct_) add_direct_light(*direct_, frame, out);
  }

 private:
  using Chain = ReservoirChain<B, PathReservoir>;

  void render_chain(const FrameInfo& frame, int s, Chain& c) {
    using namespace pt_frame_detail;
    const Options& o = ctx_.options;
    const ReuseFrame f{uint32_t(frame.index), o.render.seed, uint32_t(s)};
    const FrameWorld<Tracer>& fw = world_.view();
    c.begin_frame(world_, ctx_, frame, s);
    {
      StageTimer timer(frame.stages, "candidates");
      Exec::for_pixels(c.width, c.height, CandidateStage<Tracer>{fw, settings_, o.pt.candidates, f, c.view(), c.reservoirs.data},
                       "ReSTIR PT initial paths", frame.progress);
    }
    const PlantedBias planted = ctx_.planted ? *ctx_.planted : PlantedBias{};
    c.reuse(o.pt.reuse, frame,
            PtBridges<Tracer>{fw, settings_, o.pt.history_scene == HistoryScene::previous, planted, ctx_.planted != nullptr}, f);
    {
      StageTimer timer(frame.stages, "shading");
      const ShadeStage stage{c.view(), c.reservoirs.data, direct_ != nullptr, o.render.debug_view, c.debug(), sum_.data};
      Exec::for_pixels(c.width, c.height, stage, "ReSTIR PT shading");
    }
    if (o.render.debug_view == DebugView::reconnection_depth) {
      std::vector<PathReservoir> host(size_t(c.width) * size_t(c.height));
      Exec::download(host.data(), c.reservoirs, host.size());
      print_reconnection_histogram(frame.index, s, host);
    }
    c.end_frame();
  }

  RenderContext ctx_;
  PathSettings settings_;
  typename B::World world_;
  std::vector<std::unique_ptr<Chain>> chains_;
  typename Exec::template Array<Rgb> sum_;
  std::unique_ptr<Integrator> direct_;
};

}  // namespace rl
