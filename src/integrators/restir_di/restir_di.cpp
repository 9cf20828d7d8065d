// ReSTIR DI (Bitterli et al. 2020, "Spatiotemporal reservoir resampling for real-time ray tracing
// with dynamic direct lighting"): per pixel, resampled light samples are reused from the previous
// frame and from neighbouring pixels, then shaded with one sample. Direct lighting only (the
// reference is the path tracer at path.max_depth = 1). All resampling math lives in src/restir;
// the pixel bookkeeping of reuse in reuse_passes.h.
#include <optional>

#include "frame/cuda_maker.h"
#include "integrators/restir_di/di_sampling.h"
#include "integrators/path/path_tracer.h"
#include "frame/restir_cuda.h"
#include "frame/reuse_passes.h"

namespace rl {

namespace {

// The bridge of mis.h for DI: the identity shift (all domains share the emitters' area measure),
// targets evaluated at each domain's own primary surface.
// In an animated scene the temporal pass's history (domain 1) lives in the previous frame: its
// samples move with their emitters into this frame (Lights::follow: rigid motion, Jacobian 1 in
// area measure), and its target is the previous frame's -- the point carried back, the previous
// lights' emission (a light switched on since has none there). That keeps the history's MIS weight
// at 0 wherever the history could not have produced a sample (GRIS, Lin et al. 2022, sec. 5: the
// weights must vanish outside each domain's support), e.g. where a light moved into view;
// evaluating it with this frame's lights instead left -20 to -40 % on the dynamic room's glossy
// block (di.history_scene = current keeps that shortcut, named and measured as biased).
// Visibility in the history's target is tested in the previous frame's BVH (`history`, kept by
// the renderer when the target includes visibility): the history only holds samples that were
// visible a frame earlier, so near a moving occluder's shadow this frame's BVH would give it the
// wrong support.
struct DiBridge {
  DiViewBridge<AccelTracer> view;           // this frame's scene: everything but an animated history
  const RenderContext* ctx;
  const Lights* history_lights = nullptr;  // temporal pass of an animated scene: domain 1's lights
  bool history_in_previous = true;          // di.history_scene = previous
  const RenderContext* history = nullptr;   // temporal pass: the previous frame's scene and BVH, if kept
  bool shift_to_canonical(int i, const LightPoint& y, LightPoint& x, float& jacobian) const {
    x = y;
    jacobian = 1;
    Vec3 normal;  // follow's; a LightPoint derives its normal from its emitter
    if (i == 1 && history_lights) return ctx->lights.follow(y.emitter, *history_lights, x.position, normal);
    return true;
  }
  bool stored_target_valid(int i) const { return view.stored_target_valid(i); }
  float target_from(int i, const LightPoint& x) const {
    if (i == 1 && history_in_previous && (history_lights || history)) {
      LightPoint back = x;  // where x was one frame earlier
      Vec3 normal;
      if (history_lights && !history_lights->follow(x.emitter, ctx->lights, back.position, normal)) return 0;
      return di_target(history ? *history : *ctx, history_lights ? *history_lights : ctx->lights, *view.surfaces[1], back,
                       view.other_visibility);
    }
    return view.target_from(i, x);
  }
};

class RestirDi final : public Integrator {
 public:
  explicit RestirDi(const RenderContext& ctx) : ctx_(ctx) {}

  // The previous frame's BVH when the history's target includes visibility (see DiBridge).
  bool needs_previous_scene() const override {
    const DiOptions& di = ctx_.options.di;
    return scene_animated(ctx_.scene) && di.reuse.temporal && di.history_scene == HistoryScene::previous &&
           di.visibility_reuse && di.neighbor_visibility;
  }

  void render_frame(const FrameInfo& frame, Image& out) override {
    render_chains(chains_, ctx_.options.render.spp, out,
                  [&](int s, Chain& c, std::vector<Rgb>& sum) { render_chain(frame, s, c, sum); });
  }

 private:
  using Chain = ReservoirChain<LightPoint>;

  void render_chain(const FrameInfo& frame, int s, Chain& c, std::vector<Rgb>& sum) {
    const Options& o = ctx_.options;
    const DiOptions& di = o.di;
    const ReuseOptions& rp = di.reuse;
    const int w = frame.camera->width(), h = frame.camera->height();
    const uint32_t f = uint32_t(frame.index), chain = uint32_t(s);
    const uint64_t seed = o.render.seed;
    c.begin_frame(ctx_, frame, s);
    const GBuffer& g = c.gbuffer;
    const std::optional<RenderContext> history = previous_context(ctx_, frame);
    const bool static_scene = !scene_animated(ctx_.scene);  // once per frame: it scans the scene
    const PathWorld world = path_world(ctx_);
    const AccelTracer tracer{&ctx_.accel};
    auto make_bridge = [&](const GSurface* const* surfaces, int, bool temporal) {
      return DiBridge{{&world, &tracer, surfaces, di.visibility_reuse, di.visibility_reuse && di.neighbor_visibility, temporal, static_scene},
                      &ctx_,
                      temporal ? frame.previous_lights : nullptr,
                      di.history_scene == HistoryScene::previous,
                      temporal && history && !(ctx_.planted && ctx_.planted->history_visibility_now) ? &*history : nullptr};
    };

    // 1. Initial candidates (their emitters, and environment directions, from pre-sampled light
    // tiles unless di.light_tiles = 0).
    if (di.light_tiles > 0 && di.light_candidates > 0) {
      StageTimer timer(frame.stages, "light_tiles");
      tiles_.build(ctx_.lights, di.light_tiles, di.light_tile_size, f, seed, chain, di.env_tile_size);
    } else {
      tiles_.build(ctx_.lights, 0, 0, f, seed, chain);
    }
    {
      StageTimer timer(frame.stages, "candidates");
      parallel_for_pixels(w, h, [&](int x, int y) {
        const uint32_t p = uint32_t(y * w + x);
        Pcg32 rng = make_rng(p, f, RngPass::light_candidates, seed, chain);
        c.reservoirs[p] = di_initial_reservoir(world, ctx_, g.at(x, y), di.light_candidates, di.bsdf_candidates, di.visibility_reuse,
                                               rng, tiles_.tile_of(x, y, w, f, seed, chain), tiles_.env_tile_of(x, y, w, f, seed, chain));
      }, frame.progress);
    }

    // 2. Temporal reuse, 3. spatial reuse.
    c.reuse(rp, frame, make_bridge, seed, s);

    // 4. Shading: f(y) W, with visibility traced unless the target already included it.
    StageTimer timer(frame.stages, "shading");
    const ReuseDebugView dv = c.debug.view();
    parallel_for_pixels(w, h, [&](int x, int y) {
      const uint32_t p = uint32_t(y * w + x);
      if (add_debug_view(o.render.debug_view, c.reservoirs[p], dv, p, sum.data())) return;
      sum[p] += di_shade(world, tracer, g.at(x, y), c.reservoirs[p], di.visibility_reuse, p, f, seed, chain);
    });

    c.end_frame();
  }

  RenderContext ctx_;
  std::vector<Chain> chains_;
  LightTiles tiles_;  // this frame's, rebuilt per chain
};

}  // namespace

std::unique_ptr<Integrator> make_restir_di(const RenderContext& ctx) {
  if (ctx.options.render.debug_view == DebugView::reconnection_depth)
    throw OptionError("render.debug_view: reconnection-depth belongs to restir-pt (DI samples have no path)");
  if (ctx.options.render.backend == Backend::cuda) return make_on_cuda(&make_cuda_restir_di, ctx);
  return std::make_unique<RestirDi>(ctx);
}

}  // namespace rl
