// The reference: a unidirectional path tracer with next-event estimation and multiple importance
// sampling (Veach 1997, ch. 9), structured as pbrt-v4's PathIntegrator so that its images can be
// compared with pbrt's. Every ReSTIR variant is judged against it.
#include "integrators/path_tracer.h"

#include <algorithm>
#include <atomic>
#include <span>

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

bool path_bounce(const RenderContext& ctx, const PathOptions& opt, PathState& st, const Hit* hit, PendingShadow& shadow,
                 bool skip_first_emission) {
  const Scene& scene = ctx.scene;
  const Lights& lights = ctx.lights;
  const float eps = ctx.accel.ray_epsilon();
  const bool nee = opt.nee && !lights.empty();
  const int depth = st.depth;
  shadow.valid = false;
  if (!hit) {
    if (depth == 0 && skip_first_emission) return false;
    Rgb Le = lights.environment_radiance(st.ray.d);
    if (!is_black(Le)) {
      float w = 1;
      if (depth > 0 && !st.specular && nee) w = mis_weight(opt.mis, st.prev_pdf, lights.environment_pdf(st.ray.d));
      st.L += st.beta * Le * w;
    }
    return false;
  }
  SurfaceInteraction si = ctx.accel.interaction(st.ray, *hit);

  // Emission seen along the ray, MIS-weighted against light sampling from the previous vertex.
  uint32_t emitter = si.is_sphere ? lights.sphere_emitter(si.prim) : lights.triangle_emitter(si.geom, si.prim);
  if (emitter != kNoEmitter && !(depth == 0 && skip_first_emission)) {
    Rgb Le = lights.emitted(emitter, si.ng, -st.ray.d);
    if (!is_black(Le)) {
      float w = 1;
      if (depth > 0 && !st.specular && nee) w = mis_weight(opt.mis, st.prev_pdf, lights.pdf(emitter, st.prev_p, si.p, si.ng));
      st.L += st.beta * Le * w;
    }
  }
  if (depth >= opt.max_depth) return false;

  const Material& mat = scene.materials[size_t(si.material)];
  const Bsdf bsdf = make_bsdf(mat, material_reflectance(scene, mat, si.uv));
  const Frame frame = Frame::from_normal(si.ns);
  const Vec3 wo = frame.to_local(-st.ray.d);
  const bool delta = bsdf_is_delta(bsdf);
  Pcg32& rng = st.rng;

  // Next-event estimation: one light sample, MIS-weighted against BSDF sampling; the caller traces
  // the shadow ray and adds the contribution if it is unoccluded.
  if (nee && !delta) {
    LightSample ls;
    if (lights.sample(si.p, rng.next_float(), rng.next_2d(), ls) && ls.pdf > 0 && !is_black(ls.radiance)) {
      Vec3 wi = frame.to_local(ls.wi);
      Rgb f = bsdf_eval(bsdf, wo, wi) * std::fabs(wi.z);
      if (!is_black(f)) {
        float w = ls.is_delta ? 1.0f : mis_weight(opt.mis, ls.pdf, direction_pdf(bsdf, opt.bsdf_sampling, wo, wi));
        shadow.ray = shadow_ray_to_light(si.p, si.ng, ls, eps);
        shadow.contribution = st.beta * f * ls.radiance * (w / ls.pdf);
        shadow.valid = true;
      }
    }
  }

  // Continue the path.
  BsdfSample bs;
  const float u_lobe = rng.next_float();
  const Vec2 u_dir = rng.next_2d();
  if (!sample_direction(bsdf, opt.bsdf_sampling, wo, u_lobe, u_dir, bs) || bs.pdf <= 0 || is_black(bs.f)) return false;
  st.beta *= bs.f * (std::fabs(bs.wi.z) / bs.pdf);
  st.specular = bs.is_delta;
  st.prev_pdf = bs.pdf;
  st.prev_p = si.p;
  const Vec3 wi_world = frame.to_world(bs.wi);
  st.ray = spawn_ray(si.p, si.ng, wi_world, eps);
  st.depth = depth + 1;

  // Russian roulette (pbrt-v4): survive with probability max(beta) once past rr_min_depth.
  if (opt.russian_roulette && depth + 1 >= opt.rr_min_depth) {
    float m = max_component(st.beta);
    if (m < 1) {
      float q = std::max(0.0f, 1 - m);
      if (rng.next_float() < q) return false;
      st.beta /= 1 - q;
    }
  }
  return true;
}

namespace {
// path_radiance's loop; `first` (when set) is the closest hit of `ray` already found by the
// caller, *first_found whether there was one.
Rgb trace_path(const RenderContext& ctx, const PathOptions& opt, Ray ray, Pcg32& rng, PathStats* stats,
               bool skip_first_emission, const Hit* first, bool first_found) {
  PathState st;
  st.ray = ray;
  st.rng = rng;
  for (bool known = first != nullptr;; known = false) {
    Hit hit;
    bool found;
    if (known) {
      found = first_found;
      if (found) hit = *first;
    } else {
      if (stats) {
        ++stats->rays;
        if (stats->record_rays) stats->record_rays->push_back(st.ray);
      }
      found = ctx.accel.intersect(st.ray, hit);
    }
    PendingShadow shadow;
    const bool alive = path_bounce(ctx, opt, st, found ? &hit : nullptr, shadow, skip_first_emission);
    if (shadow.valid) {
      if (stats) {
        ++stats->shadow_rays;
        if (stats->record_shadow_rays) stats->record_shadow_rays->push_back(shadow.ray);
      }
      if (!ctx.accel.occluded(shadow.ray)) st.L += shadow.contribution;
    }
    if (!alive) break;
  }
  rng = st.rng;
  return st.L;
}
}  // namespace

Rgb path_radiance(const RenderContext& ctx, const PathOptions& opt, Ray ray, Pcg32& rng, PathStats* stats,
                  bool skip_first_emission) {
  return trace_path(ctx, opt, ray, rng, stats, skip_first_emission, nullptr, false);
}

Rgb path_radiance_from_hit(const RenderContext& ctx, const PathOptions& opt, const Ray& ray, const Hit* hit, Pcg32& rng) {
  const Hit none;
  return trace_path(ctx, opt, ray, rng, nullptr, false, hit ? hit : &none, hit != nullptr);
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

// The reference integrator as a wavefront (issue 9): paths advance bounce by bounce in waves of
// kWave (pixel, sample) paths, each stage a parallel loop over a flat buffer -- camera rays, one
// batched closest-hit query (the backend's RayQueries: Embree's stream API on the CPU), shading (path_bounce), one batched occlusion
// query for next-event estimation, compaction of the live paths -- instead of one pixel's whole
// path at a time. Each path keeps its own random stream and runs path_bounce, so the image equals
// path_radiance's (tests/test_path_tracer.cpp) whatever the thread count.
class PathTracer final : public Integrator {
 public:
  explicit PathTracer(const RenderContext& ctx) : ctx_(ctx) {}

  void render_frame(const FrameInfo& frame, Image& out) override {
    const Options& o = ctx_.options;
    const size_t spp = size_t(o.render.spp), pixels = out.size(), total = pixels * spp;
    sum_.assign(pixels, Rgb(0));
    const size_t waves = (total + kWave - 1) / kWave;
    for (size_t wave = 0; wave < waves; ++wave) {
      const size_t begin = wave * kWave, n = std::min(kWave, total - begin);
      start_paths(frame, out.width, begin, n);
      for (int depth = 0; !live_.empty(); ++depth) trace_bounce(frame, depth == 0);
      // Pixel sums in path order (a pixel's samples in order): the same floats whatever the threads.
      for (size_t i = 0; i < n; ++i) sum_[(begin + i) / spp] += paths_[i].L;
      if (frame.progress) frame.progress(int(wave + 1), int(waves));
    }
    for (size_t i = 0; i < pixels; ++i) out.pixels[i] = sum_[i] / float(spp);  // non-finite values: the driver reports them
  }

 private:
  static constexpr size_t kWave = size_t(1) << 16;  // paths in flight: their state stays in the caches
  static constexpr int kChunk = 256;                // paths per parallel task

  template <class Fn>
  static void parallel_chunks(size_t n, const Fn& fn) {  // fn(first, end) over [0, n) in chunks
    parallel_for(int((n + kChunk - 1) / kChunk), [&](int c) { fn(size_t(c) * kChunk, std::min(n, size_t(c + 1) * kChunk)); });
  }

  void start_paths(const FrameInfo& frame, int width, size_t begin, size_t n) {
    StageTimer timer(frame.stages, "camera");
    const Options& o = ctx_.options;
    const uint32_t spp = uint32_t(o.render.spp);
    paths_.resize(n);
    live_.resize(n);
    parallel_chunks(n, [&](size_t a, size_t b) {
      for (size_t i = a; i < b; ++i) {
        const size_t index = begin + i;
        const uint32_t pixel = uint32_t(index / spp), s = uint32_t(index % spp);
        const int x = int(pixel % uint32_t(width)), y = int(pixel / uint32_t(width));
        PathState& st = paths_[i];
        st = PathState{};
        st.ray = camera_ray(ctx_, *frame.camera, x, y, frame.index, int(s));
        st.rng = make_rng(pixel, uint32_t(frame.index), RngPass::path, o.render.seed, s);
        live_[i] = uint32_t(i);
      }
    });
  }

  // One bounce of every live path: closest hits, shading, shadow rays, compaction.
  void trace_bounce(const FrameInfo& frame, bool primary) {
    const size_t n = live_.size();
    rays_.resize(n);
    hits_.resize(n);
    shadows_.resize(n);
    alive_.resize(n);
    {
      StageTimer timer(frame.stages, "intersect");
      parallel_chunks(n, [&](size_t a, size_t b) {
        for (size_t k = a; k < b; ++k) rays_[k] = paths_[live_[k]].ray;
      });
      ctx_.rays().intersect_batch(rays_, hits_, primary);
    }
    {
      StageTimer timer(frame.stages, "shade");
      parallel_chunks(n, [&](size_t a, size_t b) {
        for (size_t k = a; k < b; ++k)
          alive_[k] = path_bounce(ctx_, ctx_.options.path, paths_[live_[k]], hits_[k].valid() ? &hits_[k] : nullptr, shadows_[k]);
      });
    }
    {
      StageTimer timer(frame.stages, "shadow");
      shadow_rays_.clear();
      shadow_owner_.clear();
      for (size_t k = 0; k < n; ++k)
        if (shadows_[k].valid) {
          shadow_rays_.push_back(shadows_[k].ray);
          shadow_owner_.push_back(uint32_t(k));
        }
      blocked_.resize(shadow_rays_.size());
      ctx_.rays().occluded_batch(shadow_rays_, blocked_);
      parallel_chunks(shadow_rays_.size(), [&](size_t a, size_t b) {
        for (size_t j = a; j < b; ++j)  // one shadow ray per path and bounce: no two tasks touch one path
          if (!blocked_[j]) paths_[live_[shadow_owner_[j]]].L += shadows_[shadow_owner_[j]].contribution;
      });
    }
    size_t kept = 0;
    for (size_t k = 0; k < n; ++k)
      if (alive_[k]) live_[kept++] = live_[k];
    live_.resize(kept);
  }

  RenderContext ctx_;
  // Buffers of the wavefront, allocated once and reused by every wave and frame.
  std::vector<PathState> paths_;
  std::vector<uint32_t> live_;  // indices into paths_ of the paths still being traced, in order
  std::vector<Ray> rays_, shadow_rays_;
  std::vector<Hit> hits_;
  std::vector<PendingShadow> shadows_;
  std::vector<uint8_t> alive_, blocked_;
  std::vector<uint32_t> shadow_owner_;
  std::vector<Rgb> sum_;
};

}  // namespace

std::unique_ptr<Integrator> make_path_tracer(const RenderContext& ctx) {
  if (ctx.options.render.debug_view != DebugView::none)
    throw OptionError("render.debug_view: the path tracer has no debug views (they belong to the ReSTIR integrators)");
  return std::make_unique<PathTracer>(ctx);
}

}  // namespace rl
