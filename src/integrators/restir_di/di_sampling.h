// ReSTIR DI's sample space and target function (Bitterli et al. 2020, §3-4). A DI sample is a
// point on an emitter (area measure), a direction of the environment (solid angle) or a point
// light (counting measure). These measures do not depend on the shading point, so the shift
// between pixels is the identity with jacobian 1 and a reservoir can be reused as is.
#pragma once
#include <span>
#include <vector>

#include "core/rng.h"
#include "integrators/restir_di/di_kernel.h"
#include "integrators/restir_di/restir_di_pixel.h"
#include "frame/gbuffer.h"
#include "restir/reservoir.h"

namespace rl {


// di_pixel.h's Tracer on the CPU: Embree, one ray at a time.
struct AccelTracer {
  const Accel* accel;
  bool occluded(const Ray& r) const { return accel->occluded(r); }
  bool intersect(const Ray& r, Hit& hit) const { return accel->intersect(r, hit); }
};

// Pre-sampled light tiles (Wyman and Panteleev 2021, "Rearchitecting spatiotemporal resampling for
// production", §4.1; RTXDI's presampling pass): each frame, `count` tiles of `size` emitters drawn
// independently from the light selection distribution; every pixel of a 16x16-pixel block draws
// its light candidates' emitters uniformly from one tile, so they come from a few kilobytes that
// stay in cache instead of from the whole light list. Each entry, hence each candidate, is
// marginally distributed by the selection pmf, so the candidates' source pdf is unchanged and the
// estimator stays unbiased: the resampling weights need only each candidate's marginal density,
// and correlated candidates are allowed (Lin et al. 2022, GRIS §4, the unbiasedness of
// E[f(Y) W] = sum_i E[m_i(X_i) f(X_i) / p_i(X_i)] uses linearity of expectation only).
// Each tile also holds `env_size` directions drawn from the environment map's importance
// distribution (RTXDI's environment presampling, ibid.): a candidate whose emitter is the
// environment takes one of them uniformly instead of sampling the map itself -- a random texel of a
// large image and two table lookups, the cache misses that dominated env-lit frames. Each entry is
// marginally distributed by the environment's density, so the same argument keeps it unbiased.
class LightTiles {
 public:
  // Draws the tiles of one frame (count 0: no tiles, candidates select from the whole list).
  void build(const Lights& lights, int count, int size, uint32_t frame, uint64_t seed, uint32_t chain, int env_size = 0);
  // The tile of pixel (x, y), chosen at random per 16x16-pixel block and frame; empty without tiles.
  std::span<const LightTileEntry> tile_of(int x, int y, int width, uint32_t frame, uint64_t seed, uint32_t chain) const;
  // The same tile's environment directions; empty without tiles, environment or env_size.
  std::span<const EnvTileEntry> env_tile_of(int x, int y, int width, uint32_t frame, uint64_t seed, uint32_t chain) const;
  static constexpr int kBlockPixels = kLightTileBlockPixels;
  // The tiles as flat arrays (count() tiles of size() entries, env_size() environment directions
  // each), for the CUDA backend's copy; light_tile_index picks a pixel's.
  int count() const { return count_; }
  int size() const { return size_; }
  int env_size() const { return env_size_; }
  const std::vector<LightTileEntry>& entries() const { return entries_; }
  const std::vector<EnvTileEntry>& env_entries() const { return env_entries_; }

 private:
  size_t tile_index(int x, int y, int width, uint32_t frame, uint64_t seed, uint32_t chain) const;
  int count_ = 0, size_ = 0, env_size_ = 0;
  std::vector<LightTileEntry> entries_;
  std::vector<EnvTileEntry> env_entries_;
};

// The DI integrand at surface s for light point y, without visibility: f(wo, wi) |cos θ_s| Le G,
// G = |cos θ_l| / d² for area emitters (area measure), 1/d² for point lights, 1 for the environment.
// `shadow_ray` receives the ray that tests the visibility of y from s.
Rgb di_unshadowed(const Lights& lights, const GSurface& s, const LightPoint& y, float eps, Ray* shadow_ray = nullptr);

// Target function p̂ = luminance of the unshadowed integrand (times visibility when `visibility`).
float di_target(const RenderContext& ctx, const GSurface& s, const LightPoint& y, bool visibility);
// The same with other lights (an animated scene's previous frame), visibility in ctx's BVH.
float di_target(const RenderContext& ctx, const Lights& lights, const GSurface& s, const LightPoint& y, bool visibility);

// Initial resampling (Talbot et al. 2005 RIS with the balance heuristic over the two strategies):
// light_candidates from the light sampler (emitter by the selection pmf -- from `tile` when given,
// see LightTiles -- then a point on it for this surface, Lights::sample_emitter: the visible cap of
// a sphere, uniform by area on triangles) and bsdf_candidates by tracing BSDF samples to emitters,
// each with resampling weight p̂(x) / (M_l p_l(x) + M_b p_b(x)) (pdfs in the sample measure).
// Confidence = M_l + M_b. With `visibility`, the chosen sample is shadow-tested and its weight
// zeroed if occluded, making the reservoir's target p̂·V (Bitterli et al. 2020, §4.4 "visibility reuse").
// A light candidate that picks the environment takes its direction from env_tile when it is given
// (LightTiles), instead of sampling the map. w: path_world(ctx), built once per stage rather than
// copied per pixel.
DiReservoir di_initial_reservoir(const PathWorld& w, const RenderContext& ctx, const GSurface& s, int light_candidates, int bsdf_candidates,
                                 bool visibility, Pcg32& rng, std::span<const LightTileEntry> tile = {},
                                 std::span<const EnvTileEntry> env_tile = {});

// Direct light through a delta BSDF (mirror, smooth glass), which resampling cannot handle:
// follows the specular direction and returns the throughput-weighted emission it sees.
Rgb di_specular(const RenderContext& ctx, const GSurface& s, Pcg32& rng);

}  // namespace rl
