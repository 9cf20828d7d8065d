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
#include "frame/direction_sampling.h"
#include "frame/pixel_sampler.h"
#include "integrators/path/path_frame.h"
#include "frame/bvh_backend.h"
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

RL_WIDEST void shade_paths(const PathWorld& world, const PathOptions& po, PathState* paths, const uint32_t* live, const Hit* hits,
                           PendingShadow* shadows, uint8_t* alive, size_t a, size_t b) {
  for (size_t k = a; k < b; ++k) alive[k] = path_bounce(world, po, paths[live[k]], hits[k].valid() ? &hits[k] : nullptr, shadows[k]);
}

RL_WIDEST void start_path_range(const CameraSampling& cs, const PerspectiveCamera& camera, int frame, int width, uint32_t spp,
                                size_t begin, PathState* paths, uint32_t* live, size_t a, size_t b) {
  for (size_t i = a; i < b; ++i) start_path(cs, camera, frame, width, spp, begin, paths, live, i);
}

void check_path_tracer(const RenderContext& ctx) {
  refuse_debug_views(ctx, "the path tracer has no debug views (they belong to the ReSTIR integrators)");
}

std::unique_ptr<Integrator> make_path_tracer(const RenderContext& ctx) { return make_on_host<PathFrame>(ctx); }

}  // namespace rl
