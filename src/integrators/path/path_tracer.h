#pragma once
#include <vector>

#include "core/rng.h"
#include "frame/integrator.h"
#include "integrators/path/path_pixel.h"

namespace rl {

// Counters of one radiance estimate, summed by the caller (benchmarks report rays/s).
struct PathStats {
  uint64_t rays = 0;          // closest-hit rays
  uint64_t shadow_rays = 0;   // occlusion rays
  // Benchmarks only: when set, every traced ray is appended here (to replay them through Embree
  // alone and measure the share of frame time spent in traversal).
  std::vector<Ray>* record_rays = nullptr;
  std::vector<Ray>* record_shadow_rays = nullptr;
};

// Radiance arriving along `ray` (pbrt-v4 PathIntegrator::Li): emission, next-event estimation and
// BSDF sampling combined with MIS, Russian roulette. Shared by the reference integrator and the
// ReSTIR integrators for their reference/path parts.
// skip_first_emission drops the emission of the first surface hit (ReSTIR GI's sample points carry
// reflected radiance only; their emission is direct light at the visible point, estimated by NEE).
Rgb path_radiance(const RenderContext& ctx, const PathOptions& opt, Ray ray, Pcg32& rng, PathStats* stats = nullptr,
                  bool skip_first_emission = false);

// path_radiance of a ray whose closest hit the caller already has (hit null: the ray escaped),
// e.g. a G-buffer's primary hit: the same random numbers and the same result, one ray fewer.
Rgb path_radiance_from_hit(const RenderContext& ctx, const PathOptions& opt, const Ray& ray, const Hit* hit, Pcg32& rng);


}  // namespace rl
