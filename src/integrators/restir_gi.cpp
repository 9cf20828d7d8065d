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
#include "integrators/path_tracer.h"
#include "integrators/planted_bias.h"
#include "integrators/reuse_passes.h"
#include "restir/shift.h"

namespace rl {

namespace {

struct GiSample {
  Vec3 position;      // x_s, or the direction when the ray escaped to the environment
  Vec3 normal;        // geometric normal at x_s
  bool infinite = false;
  Rgb radiance{0};    // reflected L_o(x_s -> visible point), estimated by a path from x_s
  uint32_t geom = kInvalidId, prim = kInvalidId;  // the surface of x_s (its animation moves it)
  Pcg32 suffix;       // the random stream of the path that estimated `radiance` (replayed across frames)
};
using GiReservoir = restir::Reservoir<GiSample>;

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

// f_s(wo, wi) |cos| L_o at visible surface s for sample x (no visibility).
Rgb gi_integrand(const GSurface& s, const GiSample& x) {
  if (!s.valid) return Rgb(0);
  Vec3 wi = x.position;
  if (!x.infinite) {
    const Vec3 d = x.position - s.p;
    const float len = length(d);
    if (!(len > 0)) return Rgb(0);
    wi = d / len;
  }
  const Vec3 wo_l = s.frame.to_local(s.wo), wi_l = s.frame.to_local(wi);
  const Rgb v = bsdf_eval(s.bsdf, wo_l, wi_l) * std::fabs(wi_l.z) * x.radiance;
  return is_finite(v) ? max(v, Rgb(0)) : v;  // non-finite: reported by the render driver, never hidden
}

float gi_target(const RenderContext& ctx, GiTarget kind, const GSurface& s, const GiSample& x, bool visibility) {
  const Rgb v = gi_integrand(s, x);
  if (is_black(v)) return 0;
  if (visibility) {
    const float eps = ctx.accel.ray_epsilon();
    const Ray r = x.infinite ? spawn_ray(s.p, s.ng, x.position, eps) : spawn_ray_to(s.p, s.ng, x.position, x.normal, eps);
    if (ctx.accel.occluded(r)) return 0;
  }
  return luminance(kind == GiTarget::radiance ? x.radiance : v);
}

// Solid angle at `from` -> at `to` for the same sample point (1 for the environment).
float gi_jacobian(const GiSample& x, Vec3 from, Vec3 to) {
  return x.infinite ? 1.0f : restir::reconnection_jacobian(from, to, x.position, x.normal);
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
  const RenderContext* ctx;
  GiTarget kind;
  const GSurface* const* surfaces;
  const GiMotion* motion = nullptr;  // temporal pass of an animated scene
  bool shift_to_canonical(int i, const GiSample& y, GiSample& x, float& jacobian) const {
    if (i == 1 && motion) {
      x = replayed(*ctx, *motion->path, *surfaces[0], carried(ctx->scene, motion->forward, y));
      jacobian = x.infinite ? 1.0f
                            : restir::moved_reconnection_jacobian(surfaces[1]->p, y.position, y.normal, surfaces[0]->p,
                                                                  x.position, x.normal);
      return jacobian > 0;
    }
    x = y;
    jacobian = gi_jacobian(y, surfaces[i]->p, surfaces[0]->p);
    return jacobian > 0;
  }
  float target_from(int i, const GiSample& x) const {
    if (i == 1 && motion) {
      const GiSample back = replayed(*motion->previous, *motion->path, *surfaces[1], carried(ctx->scene, motion->back, x));
      const float t = gi_target(*motion->previous, kind, *surfaces[1], back, false);  // visibility: in replayed
      return x.infinite ? t
                        : t * restir::moved_reconnection_jacobian(surfaces[0]->p, x.position, x.normal, surfaces[1]->p,
                                                                  back.position, back.normal);
    }
    const float t = gi_target(*ctx, kind, *surfaces[i], x, true);
    return i == 0 ? t : t * gi_jacobian(x, surfaces[0]->p, surfaces[i]->p);
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

  // One BSDF-sampled secondary hit and the radiance leaving it toward s (a path of max_depth - 1 bounces).
  GiReservoir initial(const GSurface& s, Pcg32& rng, Rgb& specular) const {
    GiReservoir r;
    r.confidence = 1;
    if (!s.valid) return r;
    BsdfSample bs;
    const float u_lobe = rng.next_float();
    const Vec2 u = rng.next_2d();
    if (!bsdf_sample(s.bsdf, s.frame.to_local(s.wo), u_lobe, u, bs) || !(bs.pdf > 0) || is_black(bs.f)) return r;
    const Vec3 wi = s.frame.to_world(bs.wi);
    const Ray ray = spawn_ray(s.p, s.ng, wi, ctx_.accel.ray_epsilon());
    if (bs.is_delta) {  // no NEE and no reconnection through a delta lobe: a plain path estimate
      specular = bs.f * std::fabs(bs.wi.z) / bs.pdf * path_radiance(ctx_, path_, ray, rng);
      return r;
    }
    GiSample x;
    x.suffix = rng;  // the stream path_radiance draws from, for replays in other frames
    x.radiance = path_radiance(ctx_, path_, ray, rng, nullptr, /*skip_first_emission=*/true);
    Hit hit;
    float pdf = bs.pdf;
    if (ctx_.accel.intersect(ray, hit)) {
      const SurfaceInteraction si = ctx_.accel.interaction(ray, hit);
      x.position = si.p;
      x.normal = si.ng;
      x.geom = si.geom;
      x.prim = si.prim;
      // The sample is valued along the direction from the visible point to x_s (as every shift
      // sees it), so its density is taken there too: the traced ray left from an offset origin, and
      // near contact (x_s within a few epsilons) the two directions differ enough to bias f/p.
      const Vec3 wi_pos = normalize(si.p - s.p);
      pdf = bsdf_pdf(s.bsdf, s.frame.to_local(s.wo), s.frame.to_local(wi_pos));
    } else {
      x.infinite = true;
      x.position = wi;
    }
    const float t = gi_target(ctx_, ctx_.options.gi.target, s, x, false);  // visible: it was traced
    if (pdf > 0) restir::stream(r, x, t, t / pdf, rng.next_float());
    restir::finalize(r);
    return r;
  }

  // Direct light at a non-delta visible point: one light sample (no MIS: the GI samples exclude
  // emission, so light sampling is the only strategy for it).
  Rgb direct(const GSurface& s, Pcg32& rng) const {
    if (!s.valid || bsdf_is_delta(s.bsdf)) return Rgb(0);
    LightSample ls;
    const float u_select = rng.next_float();
    const Vec2 u = rng.next_2d();
    if (!ctx_.lights.sample(s.p, u_select, u, ls) || !(ls.pdf > 0)) return Rgb(0);
    const Vec3 wi_l = s.frame.to_local(ls.wi);
    const Rgb f = bsdf_eval(s.bsdf, s.frame.to_local(s.wo), wi_l) * std::fabs(wi_l.z);
    if (is_black(f)) return Rgb(0);
    return ctx_.accel.occluded(shadow_ray_to_light(s.p, s.ng, ls, ctx_.accel.ray_epsilon())) ? Rgb(0) : f * ls.radiance / ls.pdf;
  }

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
    auto make_bridge = [&](const GSurface* const* surfaces, int, bool temporal) {
      const bool planted = ctx_.planted && ctx_.planted->gi_history_cached;
      return GiBridge{&ctx_, o.gi.target, surfaces, temporal && previous && !planted ? &motion : nullptr};
    };

    {
      StageTimer timer(frame.stages, "candidates");
      parallel_for_pixels(w, h, [&](int x, int y) {
        const uint32_t p = uint32_t(y * w + x);
        Pcg32 rng = make_rng(p, f, RngPass::path, seed, chain);
        c.reservoirs[p] = initial(g.at(x, y), rng, c.specular[p]);
        c.specular[p] += direct(g.at(x, y), rng);
      }, frame.progress);
    }

    c.reuse(rp, frame, make_bridge, seed, s);

    StageTimer timer(frame.stages, "shading");
    parallel_for_pixels(w, h, [&](int x, int y) {
      const uint32_t p = uint32_t(y * w + x);
      const GSurface& sf = g.at(x, y);
      Rgb dbg;
      if (debug_view_value(o.render.debug_view, c.reservoirs[p], c.debug, p, dbg)) {
        sum[p] += dbg;
        return;
      }
      Rgb L = sf.valid ? sf.emitted + c.specular[p] : sf.background;
      const GiReservoir& r = c.reservoirs[p];
      if (sf.valid && r.has_sample()) L += gi_integrand(sf, r.sample) * r.ucw;  // visible: the target included it
      mark_non_finite(r, L);
      sum[p] += L;
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
  return std::make_unique<RestirGi>(ctx);
}

}  // namespace rl
