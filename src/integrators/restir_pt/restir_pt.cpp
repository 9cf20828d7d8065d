// ReSTIR PT (Lin et al. 2022, "Generalized resampled importance sampling: foundations of ReSTIR"):
// per pixel a reservoir of full paths from the primary hit, reused from the previous frame and
// from neighbouring pixels through a shift mapping (reconnection, random replay or hybrid; see
// pt_path.h), then shaded with one path. The reference is the path tracer with the same path.*
// options (emission seen directly at the primary hit is added as is).
#include <optional>

#include "frame/cuda_maker.h"
#include "integrators/path/path_tracer.h"
#include "integrators/restir_pt/pt_path.h"
#include "integrators/restir_pt/restir_pt_pixel.h"
#include "frame/restir_cuda.h"
#include "frame/reuse_passes.h"

namespace rl {

std::unique_ptr<Integrator> make_restir_di(const RenderContext& ctx);  // registry.cpp lists both

namespace {

// The bridge of mis.h for paths: shifts evaluate the path at the other pixel's primary hit.
// In an animated scene's temporal pass (pt.history_scene = previous) domain 1 is the previous
// frame: the history's paths were traced in that frame's scene, and a path is shifted between the
// frames by random replay -- its random numbers re-traced from the other frame's primary hit in
// that frame's scene (`history`: the previous scene, its BVH and its lights). The map is the
// identity in primary sample space, so the pair of frames is a valid shift with |∂ȳ/∂x̄| =
// p(x̄)/p(ȳ), each density taken in its own scene (GRIS, Lin et al. 2022, §6.1), and the MIS
// weights see each domain's own target, which vanishes wherever that frame could not have drawn
// the path (a light switched off, an occluder moved in): the weights stay a partition of unity
// over the supports (GRIS §5), which is what unbiasedness needs.
struct PtBridge {
  const RenderContext* ctx;
  const PathWorld* world;           // ctx's views (path_world), built once per frame
  const PathSettings* ps;
  const GSurface* const* surfaces;  // surfaces[i] = domain i's primary surface, 0 = canonical
  const RenderContext* history = nullptr;  // domain 1's scene when it is another frame's; else null
  const PathWorld* history_world = nullptr;  // history's views
  // Domain 1 is last frame's pixel evaluated in this frame's scene (pt.history_scene = current in an
  // animated scene): its stored target was computed in the other scene.
  bool history_in_other_scene = false;
  mutable int shifting = 0;         // the input combine() is weighing (for planted biases only)
  // PtViewBridge's reasoning; it holds in an animated scene too as long as each domain's target is
  // evaluated in the scene its reservoir was made in. The planted biases of the tests act in
  // target_from and keep it.
  bool stored_target_valid(int i) const {
    return i > 0 && ps->check_invertibility && !ctx->planted && !(i == 1 && history_in_other_scene);
  }
  bool shift_in(int i, const PathSample& x, const GSurface& to, PathSample& y, float& jacobian) const {
    if (i == 1 && history) return shift_path(*history_world, history->accel, *ps, x, to, y, jacobian);
    return shift_path(*world, ctx->accel, *ps, x, to, y, jacobian);
  }
  bool shift_to_canonical(int i, const PathSample& y, PathSample& x, float& jacobian) const {
    shifting = i;
    const bool ok = shift_in(0, y, *surfaces[0], x, jacobian);
    if (ctx->planted) jacobian *= ctx->planted->jacobian_scale;
    return ok;
  }
  float target_from(int i, const PathSample& x) const {
    if (i == 0) return luminance(x.contribution);  // x already lives in the canonical domain
    PathSample y;
    float jacobian;
    if (!shift_in(i, x, *surfaces[i], y, jacobian)) return 0;
    float t = luminance(y.contribution) * jacobian;
    if (ctx->planted) t *= ctx->planted->jacobian_scale * (i == shifting ? ctx->planted->own_target_scale : 1.0f);
    return t;
  }
};


class RestirPt final : public Integrator {
 public:
  explicit RestirPt(const RenderContext& ctx) : ctx_(ctx), settings_(path_settings(ctx.options)) {
    // ReSTIR DI adds the direct light only to a shaded image (render_frame): under a debug view it
    // is not made, so that a view of the paths' own (reconnection-depth) does not reach ReSTIR DI,
    // which refuses it.
    if (ctx.options.pt.direct == DirectLighting::restir_di && ctx.options.render.debug_view == DebugView::none)
      direct_ = make_restir_di(ctx);
    if (ctx.planted && ctx.planted->skip_hybrid_check) settings_.check_invertibility = false;
  }

  bool needs_previous_scene() const override {
    const Options& o = ctx_.options;
    return (scene_animated(ctx_.scene) && o.pt.reuse.temporal && o.pt.history_scene == HistoryScene::previous) ||
           (direct_ && direct_->needs_previous_scene());
  }

  void render_frame(const FrameInfo& frame, Image& out) override {
    render_chains(chains_, ctx_.options.render.spp, out,
                  [&](int s, Chain& c, std::vector<Rgb>& sum) { render_chain(frame, s, c, sum); });
    // pt.direct = restir-di: ReSTIR DI renders the emission seen and the direct light (same primary
    // rays), the paths only the indirect part (length >= 3).
    if (direct_ && ctx_.options.render.debug_view == DebugView::none) add_direct_light(*direct_, frame, out);
  }

 private:
  using Chain = ReservoirChain<PathSample>;

  void render_chain(const FrameInfo& frame, int s, Chain& c, std::vector<Rgb>& sum) {
    const Options& o = ctx_.options;
    const ReuseOptions& rp = o.pt.reuse;
    const int w = frame.camera->width(), h = frame.camera->height();
    const uint32_t f = uint32_t(frame.index), chain = uint32_t(s);
    const uint64_t seed = o.render.seed;
    c.begin_frame(ctx_, frame, s);
    const GBuffer& g = c.gbuffer;
    // The previous frame's scene for the history (animated scenes, pt.history_scene = previous).
    const std::optional<RenderContext> history = previous_context(ctx_, frame);
    const PathWorld world = path_world(ctx_);
    const std::optional<PathWorld> history_world = history ? std::optional<PathWorld>(path_world(*history)) : std::nullopt;
    const bool animated = scene_animated(ctx_.scene);  // once per frame: it scans the scene
    auto make_bridge = [&](const GSurface* const* surfaces, int, bool temporal) {
      const bool past = temporal && history;
      return PtBridge{&ctx_, &world, &settings_, surfaces, past ? &*history : nullptr, past ? &*history_world : nullptr,
                      temporal && !history && animated};
    };

    // 1. Initial paths.
    {
      StageTimer timer(frame.stages, "candidates");
      parallel_for_pixels(w, h, [&](int x, int y) {
        const uint32_t p = uint32_t(y * w + x);
        const uint64_t path_seed = initial_paths_seed(seed, p, f, chain);
        c.reservoirs[p] = initial_path_reservoir(world, ctx_.accel, settings_, g.at(x, y), path_seed, o.pt.candidates);
      }, frame.progress);
    }

    // 2. Temporal reuse, 3. spatial reuse.
    c.reuse(rp, frame, make_bridge, seed, s);

    // 4. Shading: emission at the primary hit + f(Y) W.
    StageTimer timer(frame.stages, "shading");
    const ReuseDebugView dv = c.debug.view();
    parallel_for_pixels(w, h, [&](int x, int y) {
      const uint32_t p = uint32_t(y * w + x);
      const PathReservoir& r = c.reservoirs[p];
      if (add_debug_view(o.render.debug_view, r, dv, p, sum.data(), r.has_sample() ? r.sample.rc : 0)) return;
      sum[p] += pt_shade(g.at(x, y), r, direct_ != nullptr);
    });

    if (o.render.debug_view == DebugView::reconnection_depth) print_reconnection_histogram(frame.index, s, c.reservoirs);
    c.end_frame();
  }

  RenderContext ctx_;
  PathSettings settings_;
  std::vector<Chain> chains_;
  std::unique_ptr<Integrator> direct_;  // ReSTIR DI when pt.direct = restir-di
};

}  // namespace

std::unique_ptr<Integrator> make_restir_pt(const RenderContext& ctx) {
  // Temporal reuse in an animated scene (issue 11). Unbiased (pt.history_scene = previous) only by
  // random replay between the frames (see PtBridge): a reconnected path's vertex x_k and its cached
  // suffix belong to the frame that traced them and cannot be re-evaluated in another frame's
  // scene. The other shifts run with pt.history_scene = current, named as biased (its bias is
  // measured in tests/test_animation.cpp). ReSTIR DI's own temporal reuse (pt.direct = restir-di)
  // is unbiased in animated scenes.
  const Options& o = ctx.options;
  if (scene_animated(ctx.scene) && o.pt.reuse.temporal && o.pt.history_scene == HistoryScene::previous &&
      o.pt.shift != ShiftMapping::random_replay)
    throw OptionError("restir-pt: unbiased temporal reuse in an animated scene needs pt.shift=random-replay (a reconnected "
                      "path keeps the previous frame's vertices and cached radiance); set pt.shift=random-replay, or "
                      "pt.history_scene=current (biased), or pt.temporal=false");
  if (o.render.backend == Backend::cuda) return make_on_cuda(&make_cuda_restir_pt, ctx);
  return std::make_unique<RestirPt>(ctx);
}

}  // namespace rl
