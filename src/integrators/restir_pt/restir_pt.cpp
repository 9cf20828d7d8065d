// ReSTIR PT's registry entry (registry.cpp): its option checks, and its frame (restir_pt_frame.h)
// on the host backends; restir_pt.cu instantiates it for CUDA.
#include "frame/bvh_backend.h"
#include "integrators/restir_pt/restir_pt_frame.h"

namespace rl {

// pt.direct = restir-di's ReSTIR DI on the same backend (registry.cpp), under no debug view.
std::unique_ptr<Integrator> make_direct_light(const RenderContext& ctx) {
  if (ctx.options.pt.direct != DirectLighting::restir_di || ctx.options.render.debug_view != DebugView::none) return nullptr;
  return make_integrator("restir-di", ctx);
}

void check_restir_pt(const RenderContext& ctx) {
  // Temporal reuse in an animated scene (issue 11). Unbiased (pt.history_scene = previous) only by
  // random replay between the frames (see PtBridge): a reconnected path's vertex x_k and its cached
  // suffix belong to the frame that traced them and cannot be re-evaluated in another frame's
  // scene. The other shifts run with pt.history_scene = current, named as biased (its bias is
  // measured in tests/scene/test_animation.cpp). ReSTIR DI's own temporal reuse (pt.direct = restir-di)
  // is unbiased in animated scenes.
  const Options& o = ctx.options;
  if (scene_animated(ctx.scene) && o.pt.reuse.temporal && o.pt.history_scene == HistoryScene::previous &&
      o.pt.shift != ShiftMapping::random_replay)
    throw OptionError("restir-pt: unbiased temporal reuse in an animated scene needs pt.shift=random-replay (a reconnected "
                      "path keeps the previous frame's vertices and cached radiance); set pt.shift=random-replay, or "
                      "pt.history_scene=current (biased), or pt.temporal=false");
}

std::unique_ptr<Integrator> make_restir_pt(const RenderContext& ctx) { return make_on_host<RestirPtFrame>(ctx, make_direct_light(ctx)); }

}  // namespace rl
