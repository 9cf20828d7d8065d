// The reference: a unidirectional path tracer with next-event estimation and multiple importance
// sampling (Veach 1997, ch. 9), structured as pbrt-v4's PathIntegrator so that its images can be
// compared with pbrt's. Every ReSTIR variant is judged against it.
#include "integrators/path/path_tracer.h"

#include <algorithm>
#include <atomic>
#include <span>

#include "core/parallel.h"
#include "core/sampling.h"
#include "core/widest.h"
#include "frame/cuda_maker.h"
#include "frame/direction_sampling.h"
#include "frame/pixel_sampler.h"
#include "integrators/path/path_tracer_cuda.h"
#include "scene/bsdf.h"
#include "scene/texture.h"

namespace rl {

namespace {
// path_radiance's Tracer on the CPU that also counts (and, for benchmarks, records) its rays.
struct CountingTracer {
  const Accel* accel;
  PathStats* stats;
  bool intersect(const Ray& r, Hit& hit) const {
    if (stats) {
      ++stats->rays;
      if (stats->record_rays) stats->record_rays->push_back(r);
    }
    return accel->intersect(r, hit);
  }
  bool occluded(const Ray& r) const {
    if (stats) {
      ++stats->shadow_rays;
      if (stats->record_shadow_rays) stats->record_shadow_rays->push_back(r);
    }
    return accel->occluded(r);
  }
};
}  // namespace

Rgb path_radiance(const RenderContext& ctx, const PathOptions& opt, Ray ray, Pcg32& rng, PathStats* stats,
                  bool skip_first_emission) {
  return path_radiance(path_world(ctx), CountingTracer{&ctx.accel, stats}, opt, ray, rng, skip_first_emission);
}

Rgb path_radiance_from_hit(const RenderContext& ctx, const PathOptions& opt, const Ray& ray, const Hit* hit, Pcg32& rng) {
  const Hit none;  // invalid: the ray escaped
  return path_radiance(path_world(ctx), CountingTracer{&ctx.accel, nullptr}, opt, ray, rng, false, hit ? hit : &none);
}

namespace {

// One bounce (path_bounce) of paths live[a..b), on the host's widest instruction set (core/widest.h):
// the shading stage took 20% less time with the AVX2 copy (Cornell box, 640x360, 4 paired runs).
RL_WIDEST void shade_paths(const PathWorld& world, const PathOptions& po, PathState* paths, const uint32_t* live, const Hit* hits,
                           PendingShadow* shadows, uint8_t* alive, size_t a, size_t b) {
  for (size_t k = a; k < b; ++k) alive[k] = path_bounce(world, po, paths[live[k]], hits[k].valid() ? &hits[k] : nullptr, shadows[k]);
}

// Paths [a, b) of the wave that starts at path `begin`: camera rays and streams, on the widest
// instruction set as shade_paths (the camera stage: 25% less time).
RL_WIDEST void start_path_range(const CameraSampling& cs, const PerspectiveCamera& camera, int frame, int width, uint32_t spp,
                                size_t begin, PathState* paths, uint32_t* live, size_t a, size_t b) {
  for (size_t i = a; i < b; ++i) {
    const size_t index = begin + i;
    const uint32_t pixel = uint32_t(index / spp), s = uint32_t(index % spp);
    const int x = int(pixel % uint32_t(width)), y = int(pixel / uint32_t(width));
    PathState& st = paths[i];
    st = PathState{};
    st.ray = camera_ray(cs, camera, x, y, frame, int(s));
    st.rng = make_rng(pixel, uint32_t(frame), RngPass::path, cs.seed, s);
    live[i] = uint32_t(i);
  }
}

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
  static constexpr size_t kChunk = 256;             // paths per parallel task

  void start_paths(const FrameInfo& frame, int width, size_t begin, size_t n) {
    StageTimer timer(frame.stages, "camera");
    const Options& o = ctx_.options;
    const uint32_t spp = uint32_t(o.render.spp);
    paths_.resize(n);
    live_.resize(n);
    const CameraSampling cs = camera_sampling(o);
    parallel_for_chunks(n, kChunk, [&](size_t a, size_t b) {
      start_path_range(cs, *frame.camera, frame.index, width, spp, begin, paths_.data(), live_.data(), a, b);
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
      parallel_for_chunks(n, kChunk, [&](size_t a, size_t b) {
        for (size_t k = a; k < b; ++k) rays_[k] = paths_[live_[k]].ray;
      });
      ctx_.rays().intersect_batch(rays_, hits_, primary);
    }
    {
      StageTimer timer(frame.stages, "shade");
      // The views once per stage, as every stage builds them, not a ~380-byte copy per path.
      const PathWorld world = path_world(ctx_);
      const PathOptions& po = ctx_.options.path;
      parallel_for_chunks(n, kChunk, [&](size_t a, size_t b) {
        shade_paths(world, po, paths_.data(), live_.data(), hits_.data(), shadows_.data(), alive_.data(), a, b);
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
      parallel_for_chunks(shadow_rays_.size(), kChunk, [&](size_t a, size_t b) {
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
  if (ctx.options.render.backend == Backend::cuda) return make_on_cuda(&make_cuda_path_tracer, ctx);
  return std::make_unique<PathTracer>(ctx);
}

}  // namespace rl
