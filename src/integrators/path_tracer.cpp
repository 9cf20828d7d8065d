// The reference: a unidirectional path tracer with next-event estimation and multiple importance
// sampling (Veach 1997, ch. 9), structured as pbrt-v4's PathIntegrator so that its images can be
// compared with pbrt's. Every ReSTIR variant is judged against it.
#include "integrators/path_tracer.h"

#include <atomic>

#include "core/parallel.h"
#include "core/sampling.h"
#include "integrators/direction_sampling.h"
#include "integrators/pixel_sampler.h"
#include "scene/bsdf.h"
#include "scene/texture.h"

namespace rl {

namespace {

float mis_weight(MisHeuristic h, float pa, float pb) {
  return h == MisHeuristic::power ? power_heuristic(pa, pb) : balance_heuristic(pa, pb);
}

}  // namespace

Rgb path_radiance(const RenderContext& ctx, const PathOptions& opt, Ray ray, Pcg32& rng, PathStats* stats,
                  bool skip_first_emission) {
  const Scene& scene = ctx.scene;
  const Lights& lights = ctx.lights;
  const float eps = ctx.accel.ray_epsilon();
  Rgb L(0), beta(1);
  bool specular_bounce = false;
  float prev_pdf = 0;        // solid-angle pdf of the direction that produced `ray`
  Vec3 prev_p;               // the vertex `ray` left from
  const bool nee = opt.nee && !lights.empty();

  for (int depth = 0;; ++depth) {
    Hit hit;
    if (stats) {
      ++stats->rays;
      if (stats->record_rays) stats->record_rays->push_back(ray);
    }
    if (!ctx.accel.intersect(ray, hit)) {
      if (depth == 0 && skip_first_emission) break;
      Rgb Le = lights.environment_radiance(ray.d);
      if (!is_black(Le)) {
        float w = 1;
        if (depth > 0 && !specular_bounce && nee) w = mis_weight(opt.mis, prev_pdf, lights.environment_pdf(ray.d));
        L += beta * Le * w;
      }
      break;
    }
    SurfaceInteraction si = ctx.accel.interaction(ray, hit);

    // Emission seen along the ray, MIS-weighted against light sampling from the previous vertex.
    uint32_t emitter = si.is_sphere ? lights.sphere_emitter(si.prim) : lights.triangle_emitter(si.geom, si.prim);
    if (emitter != kNoEmitter && !(depth == 0 && skip_first_emission)) {
      Rgb Le = lights.emitted(emitter, si.ng, -ray.d);
      if (!is_black(Le)) {
        float w = 1;
        if (depth > 0 && !specular_bounce && nee) w = mis_weight(opt.mis, prev_pdf, lights.pdf(emitter, prev_p, si.p, si.ng));
        L += beta * Le * w;
      }
    }
    if (depth >= opt.max_depth) break;

    const Material& mat = scene.materials[size_t(si.material)];
    const Bsdf bsdf = make_bsdf(mat, material_reflectance(scene, mat, si.uv));
    const Frame frame = Frame::from_normal(si.ns);
    const Vec3 wo = frame.to_local(-ray.d);
    const bool delta = bsdf_is_delta(bsdf);

    // Next-event estimation: one light sample, MIS-weighted against BSDF sampling.
    if (nee && !delta) {
      LightSample ls;
      if (lights.sample(si.p, rng.next_float(), rng.next_2d(), ls) && ls.pdf > 0 && !is_black(ls.radiance)) {
        Vec3 wi = frame.to_local(ls.wi);
        Rgb f = bsdf_eval(bsdf, wo, wi) * std::fabs(wi.z);
        if (!is_black(f)) {
          const Ray shadow = shadow_ray_to_light(si.p, si.ng, ls, eps);
          if (stats) {
            ++stats->shadow_rays;
            if (stats->record_shadow_rays) stats->record_shadow_rays->push_back(shadow);
          }
          if (!ctx.accel.occluded(shadow)) {
            float w = ls.is_delta ? 1.0f : mis_weight(opt.mis, ls.pdf, direction_pdf(bsdf, opt.bsdf_sampling, wo, wi));
            L += beta * f * ls.radiance * (w / ls.pdf);
          }
        }
      }
    }

    // Continue the path.
    BsdfSample bs;
    const float u_lobe = rng.next_float();
    const Vec2 u_dir = rng.next_2d();
    if (!sample_direction(bsdf, opt.bsdf_sampling, wo, u_lobe, u_dir, bs) || bs.pdf <= 0 || is_black(bs.f)) break;
    beta *= bs.f * (std::fabs(bs.wi.z) / bs.pdf);
    specular_bounce = bs.is_delta;
    prev_pdf = bs.pdf;
    prev_p = si.p;
    const Vec3 wi_world = frame.to_world(bs.wi);
    ray = spawn_ray(si.p, si.ng, wi_world, eps);

    // Russian roulette (pbrt-v4): survive with probability max(beta) once past rr_min_depth.
    if (opt.russian_roulette && depth + 1 >= opt.rr_min_depth) {
      float m = max_component(beta);
      if (m < 1) {
        float q = std::max(0.0f, 1 - m);
        if (rng.next_float() < q) break;
        beta /= 1 - q;
      }
    }
  }
  return L;
}

Ray camera_ray(const RenderContext& ctx, const PerspectiveCamera& camera, int x, int y, int frame, int sample) {
  const RenderOptions& ro = ctx.options.render;
  const uint32_t pixel = uint32_t(y) * uint32_t(camera.width()) + uint32_t(x);
  Pcg32 rng = make_rng(pixel, uint32_t(frame), RngPass::camera, ro.seed, uint32_t(sample));
  const uint64_t pixel_hash = mix64(hash_combine(ro.seed, pixel));
  Vec2 u = pattern_sample(ro.sample_pattern, uint64_t(frame) * uint64_t(ro.spp) + uint64_t(sample), ro.spp, pixel_hash, rng);
  Vec2 o = filter_offset(ctx.options.film.filter, ctx.options.film.filter_radius, u, rng);
  return camera.generate_ray({float(x) + 0.5f + o.x, float(y) + 0.5f + o.y});
}

namespace {

class PathTracer final : public Integrator {
 public:
  explicit PathTracer(const RenderContext& ctx) : ctx_(ctx) {}

  void render_frame(const FrameInfo& frame, Image& out) override {
    const Options& o = ctx_.options;
    StageTimer timer(frame.stages, "paths");  // one stage: camera rays through every bounce, per pixel
    parallel_for_pixels(out.width, out.height, [&](int x, int y) {
      const uint32_t pixel = uint32_t(y) * uint32_t(out.width) + uint32_t(x);
      Rgb sum(0);
      for (int s = 0; s < o.render.spp; ++s) {
        Ray ray = camera_ray(ctx_, *frame.camera, x, y, frame.index, s);
        Pcg32 rng = make_rng(pixel, uint32_t(frame.index), RngPass::path, o.render.seed, uint32_t(s));
        sum += path_radiance(ctx_, o.path, ray, rng);  // non-finite values are reported by the render driver
      }
      out.at(x, y) = sum / float(o.render.spp);
    }, frame.progress);
  }

 private:
  RenderContext ctx_;
};

}  // namespace

std::unique_ptr<Integrator> make_path_tracer(const RenderContext& ctx) {
  if (ctx.options.render.debug_view != DebugView::none)
    throw OptionError("render.debug_view: the path tracer has no debug views (they belong to the ReSTIR integrators)");
  return std::make_unique<PathTracer>(ctx);
}

}  // namespace rl
