// ReSTIR GI (Ouyang et al. 2021, "ReSTIR GI: Path resampling for real-time path tracing"): a
// sample is a secondary hit x_s with its normal and the radiance it reflects toward the visible
// point that traced it (its own emission is direct light, estimated at the visible point by one
// light sample, as the paper leaves direct lighting to ReSTIR DI / NEE); reuse reconnects another pixel's visible point to x_s (reconnection shift,
// jacobian eq. 11) and keeps the cached radiance. That cache assumes x_s reflects the same radiance
// toward every visible point (Lambertian x_s): exact for diffuse sample points, biased otherwise —
// ReSTIR PT's reconnection evaluates x_s's BSDF instead. Reference: pt with the same path.* options.
//
// Temporal reuse in an animated scene: the cached radiance belongs to the previous frame's scene (a
// light switched off would leave a ghost), so the sample keeps the random stream of the path that
// estimated it, and the surface x_s lies on. The shift from the previous frame carries x_s with its
// object's rigid motion and re-estimates L_o by replaying that stream in this frame's scene (random
// replay of the suffix, GRIS §6.1: the identity in primary sample space, Jacobian 1); the
// reconnection Jacobian uses x_s's geometry in each frame (restir/shift.h). For the MIS weights,
// this frame's samples are carried back and replayed in the previous frame's scene and BVH. Each
// frame's target is then its own scene's, as GRIS requires; the Lambertian assumption above stays.
#include "frame/cuda_maker.h"
#include "integrators/restir_di/di_sampling.h"
#include "integrators/restir_gi/restir_gi_pixel.h"
#include "integrators/path/path_tracer.h"
#include "frame/planted_bias.h"
#include "frame/restir_cuda.h"
#include "frame/reuse_passes.h"
#include "restir/shift.h"

namespace rl {

namespace {

// The animation moving x_s's surface (-1: none).
int animation_of(const Scene& scene, const GiSample& x) {
  if (x.infinite) return -1;
  if (x.geom < scene.meshes.size()) return scene.meshes[x.geom].animation;
  if (x.geom == scene.meshes.size() && x.prim < scene.spheres.size()) return scene.spheres[x.prim].animation;
  return -1;
}

// x carried by a rigid motion per animation (motion[a]), its radiance not yet re-estimated.
GiSample carried(const Scene& scene, const std::vector<Mat4>& motion, const GiSample& x) {
  GiSample y = x;
  const int a = animation_of(scene, x);
  if (a >= 0 && size_t(a) < motion.size()) {
    y.position = motion[size_t(a)].apply_point(x.position);
    y.normal = normalize(motion[size_t(a)].apply_vector(x.normal));
  }
  return y;
}

float gi_target(const RenderContext& ctx, GiTarget kind, const GSurface& s, const GiSample& x, bool visibility) {
  return gi_target_in(path_world(ctx), AccelTracer{&ctx.accel}, kind, s, x, visibility);
}

// x with its radiance re-estimated in scene c as seen from s: x's path stream replayed from x_s
// (0 where s does not see x_s). The visibility test comes first: it spares the path.
GiSample replayed(const RenderContext& c, const PathOptions& path, const GSurface& s, GiSample x) {
  const float eps = c.accel.ray_epsilon();
  const Ray shadow = x.infinite ? spawn_ray(s.p, s.ng, x.position, eps) : spawn_ray_to(s.p, s.ng, x.position, x.normal, eps);
  x.radiance = Rgb(0);
  if (!s.valid || c.accel.occluded(shadow)) return x;
  const Vec3 dir = x.infinite ? x.position : normalize(x.position - s.p);
  Pcg32 stream = x.suffix;
  x.radiance = path_radiance(c, path, spawn_ray(s.p, s.ng, dir, eps), stream, nullptr, /*skip_first_emission=*/true);
  return x;
}

// Temporal reuse in an animated scene: domain 1 is the previous frame (see the file comment).
struct GiMotion {
  const RenderContext* previous;    // the previous frame's scene, BVH and lights
  const PathOptions* path;          // the suffix's path options
  std::vector<Mat4> back, forward;  // per animation: this frame -> the previous one, and back
};

struct GiBridge {
  GiViewBridge<AccelTracer> view;    // this frame's scene: everything but an animated history
  const RenderContext* ctx;
  const GiMotion* motion = nullptr;  // temporal pass of an animated scene
  bool history_moved = false;        // temporal pass of an animated scene, motion or not (planted)
  // The view's reasoning, except for an animated scene's history: its shift is a replay between
  // frames, and its stored target was computed in the other frame's scene.
  bool stored_target_valid(int i) const { return i > 0 && !(i == 1 && history_moved); }
  bool shift_to_canonical(int i, const GiSample& y, GiSample& x, float& jacobian) const {
    if (i == 1 && motion) {
      x = replayed(*ctx, *motion->path, *view.surfaces[0], carried(ctx->scene, motion->forward, y));
      jacobian = x.infinite ? 1.0f
                            : restir::moved_reconnection_jacobian(view.surfaces[1]->p, y.position, y.normal, view.surfaces[0]->p,
                                                                  x.position, x.normal);
      return jacobian > 0;
    }
    return view.shift_to_canonical(i, y, x, jacobian);
  }
  float target_from(int i, const GiSample& x) const {
    if (i == 1 && motion) {
      const GiSample back = replayed(*motion->previous, *motion->path, *view.surfaces[1], carried(ctx->scene, motion->back, x));
      const float t = gi_target(*motion->previous, view.kind, *view.surfaces[1], back, false);  // visibility: in replayed
      return x.infinite ? t
                        : t * restir::moved_reconnection_jacobian(view.surfaces[0]->p, x.position, x.normal, view.surfaces[1]->p,
                                                                  back.position, back.normal);
    }
    return view.target_from(i, x);
  }
};


class RestirGi final : public Integrator {
 public:
  explicit RestirGi(const RenderContext& ctx) : ctx_(ctx) {
    // The sample point's radiance comes from the reference path tracer with one bounce less.
    path_ = ctx.options.path;
    path_.max_depth = ctx.options.path.max_depth - 1;
  }

  // The previous frame's scene and BVH for temporal reuse in an animated scene (GiMotion).
  bool needs_previous_scene() const override { return scene_animated(ctx_.scene) && ctx_.options.gi.reuse.temporal; }

  void render_frame(const FrameInfo& frame, Image& out) override {
    render_chains(chains_, ctx_.options.render.spp, out,
                  [&](int s, Chain& c, std::vector<Rgb>& sum) { render_chain(frame, s, c, sum); });
  }

 private:
  struct Chain : ReservoirChain<GiSample> {
    std::vector<Rgb> specular;  // not resampled: direct light by NEE, or a plain path through a delta BSDF
  };

  void render_chain(const FrameInfo& frame, int s, Chain& c, std::vector<Rgb>& sum) {
    const Options& o = ctx_.options;
    const ReuseOptions& rp = o.gi.reuse;
    const int w = frame.camera->width(), h = frame.camera->height();
    const uint32_t f = uint32_t(frame.index), chain = uint32_t(s);
    const uint64_t seed = o.render.seed;
    c.begin_frame(ctx_, frame, s);
    const GBuffer& g = c.gbuffer;
    c.specular.assign(c.reservoirs.size(), Rgb(0));
    const std::optional<RenderContext> previous = previous_context(ctx_, frame);
    GiMotion motion{previous ? &*previous : nullptr, &path_, motion_back(ctx_.scene, frame.index), {}};
    for (const Mat4& b : motion.back) {
      Mat4 inv;
      motion.forward.push_back(b.inverse(inv) ? inv : Mat4{});
    }
    const PathWorld world = path_world(ctx_);
    const AccelTracer tracer{&ctx_.accel};
    const bool animated = scene_animated(ctx_.scene);  // once per frame: it scans the scene
    auto make_bridge = [&](const GSurface* const* surfaces, int, bool temporal) {
      const bool planted = ctx_.planted && ctx_.planted->gi_history_cached;
      return GiBridge{{&world, &tracer, o.gi.target, surfaces}, &ctx_, temporal && previous && !planted ? &motion : nullptr,
                      temporal && animated};
    };

    {
      StageTimer timer(frame.stages, "candidates");
      parallel_for_pixels(w, h, [&](int x, int y) {
        const uint32_t p = uint32_t(y * w + x);
        Pcg32 rng = make_rng(p, f, RngPass::path, seed, chain);
        c.reservoirs[p] = gi_initial_in(world, tracer, path_, o.gi.target, g.at(x, y), rng, c.specular[p]);
        c.specular[p] += gi_direct_in(world, tracer, g.at(x, y), rng);
      }, frame.progress);
    }

    c.reuse(rp, frame, make_bridge, seed, s);

    StageTimer timer(frame.stages, "shading");
    const ReuseDebugView dv = c.debug.view();
    parallel_for_pixels(w, h, [&](int x, int y) {
      const uint32_t p = uint32_t(y * w + x);
      if (add_debug_view(o.render.debug_view, c.reservoirs[p], dv, p, sum.data())) return;
      sum[p] += gi_shade(g.at(x, y), c.reservoirs[p], c.specular[p]);
    });

    c.end_frame();
  }

  RenderContext ctx_;
  PathOptions path_;
  std::vector<Chain> chains_;
};

}  // namespace

std::unique_ptr<Integrator> make_restir_gi(const RenderContext& ctx) {
  if (ctx.options.render.debug_view == DebugView::reconnection_depth)
    throw OptionError("render.debug_view: reconnection-depth belongs to restir-pt");
  if (ctx.options.render.backend == Backend::cuda) return make_on_cuda(&make_cuda_restir_gi, ctx);
  return std::make_unique<RestirGi>(ctx);
}

}  // namespace rl
