// ReSTIR DI's sample space and target function (Bitterli et al. 2020, §3-4). A DI sample is a
// point on an emitter (area measure), a direction of the environment (solid angle) or a point
// light (counting measure). These measures do not depend on the shading point, so the shift
// between pixels is the identity with jacobian 1 and a reservoir can be reused as is.
#pragma once
#include "core/rng.h"
#include "integrators/gbuffer.h"
#include "restir/reservoir.h"

namespace rl {

struct LightPoint {
  Vec3 position;               // on the emitter; the direction itself for the environment
  Vec3 normal;                 // emitter geometric normal (zero for point lights / environment)
  uint32_t emitter = kNoEmitter;
};

using DiReservoir = restir::Reservoir<LightPoint>;

// The DI integrand at surface s for light point y, without visibility: f(wo, wi) |cos θ_s| Le G,
// G = |cos θ_l| / d² for area emitters (area measure), 1/d² for point lights, 1 for the environment.
// `shadow_ray` receives the ray that tests the visibility of y from s.
Rgb di_unshadowed(const Lights& lights, const GSurface& s, const LightPoint& y, float eps, Ray* shadow_ray = nullptr);

// Target function p̂ = luminance of the unshadowed integrand (times visibility when `visibility`).
float di_target(const RenderContext& ctx, const GSurface& s, const LightPoint& y, bool visibility);

// Initial resampling (Talbot et al. 2005 RIS with the balance heuristic over the two strategies):
// light_candidates from the receiver-independent light sampler (Lights::sample_point: by power,
// then uniform by area) and bsdf_candidates by tracing BSDF samples to emitters,
// each with resampling weight p̂(x) / (M_l p_l(x) + M_b p_b(x)) (pdfs in the sample measure).
// Confidence = M_l + M_b. With `visibility`, the chosen sample is shadow-tested and its weight
// zeroed if occluded, making the reservoir's target p̂·V (Bitterli et al. 2020, §4.4 "visibility reuse").
DiReservoir di_initial_reservoir(const RenderContext& ctx, const GSurface& s, int light_candidates, int bsdf_candidates,
                                 bool visibility, Pcg32& rng);

// Direct light through a delta BSDF (mirror, smooth glass), which resampling cannot handle:
// follows the specular direction and returns the throughput-weighted emission it sees.
Rgb di_specular(const RenderContext& ctx, const GSurface& s, Pcg32& rng);

}  // namespace rl
