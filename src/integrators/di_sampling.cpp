#include "integrators/di_sampling.h"

#include <algorithm>

#include "core/parallel.h"

namespace rl {

namespace {

// Source pdfs of a light point in its sample measure, for the two candidate strategies.
struct StrategyPdfs {
  float light = 0, bsdf = 0;
};

// Converts a solid-angle pdf at p into the sample measure of y (area for area emitters).
float to_sample_measure(const Lights& lights, const LightPoint& y, Vec3 p, float pdf_solid_angle) {
  switch (lights.kind(y.emitter)) {
    case Lights::Kind::triangle:
    case Lights::Kind::sphere: {
      Vec3 d = y.position - p;
      float d2 = length_squared(d);
      if (!(d2 > 0)) return 0;
      float cos_l = std::fabs(dot(y.normal, d)) / std::sqrt(d2);
      return pdf_solid_angle * cos_l / d2;
    }
    case Lights::Kind::environment:
      return pdf_solid_angle;
    case Lights::Kind::point:
      return pdf_solid_angle;  // the selection pmf (counting measure)
  }
  return 0;
}

// Density of the light strategy at y for the receiver s (selection pmf x Lights::sample_emitter's
// density), in y's sample measure.
float light_density(const Lights& lights, const GSurface& s, const LightPoint& y) {
  if (lights.kind(y.emitter) == Lights::Kind::point) return lights.selection_pmf(y.emitter);
  return to_sample_measure(lights, y, s.p, lights.pdf(y.emitter, s.p, y.position, y.normal));
}

// light_pdf: the light strategy's density when the caller has it (a light candidate), else < 0.
StrategyPdfs strategy_pdfs(const Lights& lights, const GSurface& s, const LightPoint& y, bool need_bsdf, float light_pdf) {
  StrategyPdfs r;
  r.light = light_pdf >= 0 ? light_pdf : light_density(lights, s, y);
  const Lights::Kind kind = lights.kind(y.emitter);
  if (!need_bsdf || kind == Lights::Kind::point) return r;  // BSDF sampling never hits a point light
  const Vec3 wi = kind == Lights::Kind::environment ? y.position : normalize(y.position - s.p);
  r.bsdf = to_sample_measure(lights, y, s.p, bsdf_pdf(s.bsdf, s.frame.to_local(s.wo), s.frame.to_local(wi)));
  return r;
}

}  // namespace

Rgb di_unshadowed(const Lights& lights, const GSurface& s, const LightPoint& y, float eps, Ray* shadow_ray) {
  if (!s.valid || y.emitter == kNoEmitter) return Rgb(0);
  Vec3 wi;
  Rgb le;
  float g;
  switch (lights.kind(y.emitter)) {
    case Lights::Kind::environment:
      wi = y.position;
      le = lights.environment_radiance(wi);
      g = 1;
      if (shadow_ray) *shadow_ray = spawn_ray(s.p, s.ng, wi, eps);
      break;
    case Lights::Kind::point: {
      Vec3 d = y.position - s.p;
      float d2 = length_squared(d);
      if (!(d2 > 0)) return Rgb(0);
      wi = d / std::sqrt(d2);
      le = lights.point_intensity(y.emitter);
      g = 1 / d2;
      if (shadow_ray) *shadow_ray = spawn_ray_to(s.p, s.ng, y.position, Vec3(0), eps);
      break;
    }
    default: {
      Vec3 d = y.position - s.p;
      float d2 = length_squared(d);
      if (!(d2 > 0)) return Rgb(0);
      wi = d / std::sqrt(d2);
      le = lights.emitted(y.emitter, y.normal, -wi);
      g = std::fabs(dot(y.normal, wi)) / d2;
      if (shadow_ray) *shadow_ray = spawn_ray_to(s.p, s.ng, y.position, y.normal, eps);
      break;
    }
  }
  if (is_black(le)) return Rgb(0);
  const Vec3 wo_l = s.frame.to_local(s.wo), wi_l = s.frame.to_local(wi);
  Rgb f = bsdf_eval(s.bsdf, wo_l, wi_l) * std::fabs(wi_l.z);
  Rgb v = f * le * g;
  return is_finite(v) ? max(v, Rgb(0)) : v;  // non-finite: reported by the render driver, never hidden
}

float di_target(const RenderContext& ctx, const GSurface& s, const LightPoint& y, bool visibility) {
  Ray shadow;
  float t = luminance(di_unshadowed(ctx.lights, s, y, ctx.accel.ray_epsilon(), visibility ? &shadow : nullptr));
  if (!(t > 0)) return 0;
  if (visibility && ctx.accel.occluded(shadow)) return 0;
  return t;
}

DiReservoir di_initial_reservoir(const RenderContext& ctx, const GSurface& s, int light_candidates, int bsdf_candidates,
                                 bool visibility, Pcg32& rng, std::span<const LightTileEntry> tile) {
  DiReservoir r;
  r.confidence = float(light_candidates + bsdf_candidates);
  if (!s.valid || ctx.lights.empty() || bsdf_is_delta(s.bsdf)) return r;
  const float eps = ctx.accel.ray_epsilon();
  const float ml = float(light_candidates), mb = float(bsdf_candidates);
  // Resampling weight with the balance heuristic over the two strategies (Bitterli et al. 2020
  // eq. 4 with MIS; Veach 1997 eq. 9.10): target / (M_l p_light + M_b p_bsdf). A BSDF ray stops at
  // the first surface, so the BSDF strategy produces a light point only where it is visible from s.
  // With visibility in the target that is all that matters (occluded points have target 0). Without
  // it the target covers occluded points too, produced by light sampling alone: their BSDF density
  // is 0, which takes a shadow ray per light candidate. Counting it there (as before) left W short
  // on points occluded here and darkened the neighbours that reuse them where they are visible.
  const bool bsdf_visibility = !visibility && bsdf_candidates > 0;
  // shadow: the light candidate's shadow ray (null for BSDF candidates, visible by construction);
  // light_pdf: its light-strategy density (< 0: compute it).
  auto weight = [&](const LightPoint& y, float target, const Ray* shadow, float light_pdf) {
    if (!(target > 0)) return 0.0f;
    StrategyPdfs p = strategy_pdfs(ctx.lights, s, y, bsdf_candidates > 0, light_pdf);
    if (shadow && bsdf_visibility && p.bsdf > 0 && ctx.accel.occluded(*shadow)) p.bsdf = 0;
    float den = ml * p.light + mb * p.bsdf;
    return den > 0 ? target / den : 0.0f;
  };
  const size_t tile_size = tile.size();
  for (int i = 0; i < light_candidates; ++i) {
    const float u_select = rng.next_float();
    const Vec2 u = rng.next_2d();
    const float u_stream = rng.next_float();
    uint32_t e;
    float pmf;
    if (tile_size > 0) {  // the emitter from the pixel's tile: marginally by the selection pmf
      const LightTileEntry& t = tile[std::min(tile_size - 1, size_t(u_select * float(tile_size)))];
      e = t.emitter;
      pmf = t.pmf;
    } else {
      e = ctx.lights.select_emitter(u_select, &pmf);
    }
    LightSample ls;
    if (e == kNoEmitter || !ctx.lights.sample_emitter(e, s.p, u, ls)) continue;
    const LightPoint y{ls.position, ls.normal, e};
    const bool point = ctx.lights.kind(e) == Lights::Kind::point;
    const float light_pdf = point ? pmf : to_sample_measure(ctx.lights, y, s.p, ls.pdf * pmf);
    Ray shadow;
    float t = luminance(di_unshadowed(ctx.lights, s, y, eps, &shadow));
    restir::stream(r, y, t, weight(y, t, &shadow, light_pdf), u_stream);
  }
  const Vec3 wo_l = s.frame.to_local(s.wo);
  for (int i = 0; i < bsdf_candidates; ++i) {
    BsdfSample bs;
    float u_lobe = rng.next_float();
    Vec2 u = rng.next_2d();
    float u_stream = rng.next_float();
    if (!bsdf_sample(s.bsdf, wo_l, u_lobe, u, bs) || bs.is_delta || !(bs.pdf > 0)) continue;
    const Vec3 wi = s.frame.to_world(bs.wi);
    Hit hit;
    LightPoint y;
    if (ctx.accel.intersect(spawn_ray(s.p, s.ng, wi, eps), hit)) {
      SurfaceInteraction si = ctx.accel.interaction(Ray{s.p, wi}, hit);
      y.emitter = si.is_sphere ? ctx.lights.sphere_emitter(si.prim) : ctx.lights.triangle_emitter(si.geom, si.prim);
      y.position = si.p;
      y.normal = si.ng;
    } else if (ctx.lights.has_environment()) {
      y.emitter = ctx.lights.environment_emitter();
      y.position = wi;
    }
    if (y.emitter == kNoEmitter) continue;
    float t = luminance(di_unshadowed(ctx.lights, s, y, eps));
    restir::stream(r, y, t, weight(y, t, nullptr, -1.0f), u_stream);
  }
  restir::finalize(r);
  if (visibility && r.has_sample() && !(di_target(ctx, s, r.sample, true) > 0)) {
    r.ucw = 0;
    r.target = 0;
  }
  return r;
}

void LightTiles::build(const Lights& lights, int count, int size, uint32_t frame, uint64_t seed, uint32_t chain) {
  count_ = lights.empty() ? 0 : count;
  size_ = size;
  entries_.resize(size_t(std::max(count_, 0)) * size_t(std::max(size_, 0)));
  if (count_ <= 0 || size_ <= 0) return;
  parallel_for(count_, [&](int t) {  // one stream per tile: the same tiles whatever the thread count
    Pcg32 rng = make_rng(uint32_t(t), frame, RngPass::light_tiles, seed, chain);
    for (int i = 0; i < size_; ++i) {
      LightTileEntry& en = entries_[size_t(t) * size_t(size_) + size_t(i)];
      en.emitter = lights.select_emitter(rng.next_float(), &en.pmf);
    }
  });
}

std::span<const LightTileEntry> LightTiles::tile_of(int x, int y, int width, uint32_t frame, uint64_t seed,
                                                     uint32_t chain) const {
  if (count_ <= 0 || size_ <= 0) return {};
  const int blocks_x = (width + kBlockPixels - 1) / kBlockPixels;
  const uint32_t block = uint32_t((y / kBlockPixels) * blocks_x + x / kBlockPixels);
  Pcg32 rng = make_rng(block, frame, RngPass::light_tiles, seed, chain + 0x9e3779b9u);
  const size_t t = std::min(size_t(count_) - 1, size_t(rng.next_float() * float(count_)));
  return {entries_.data() + t * size_t(size_), size_t(size_)};
}

Rgb di_specular(const RenderContext& ctx, const GSurface& s, Pcg32& rng) {
  BsdfSample bs;
  const Vec3 wo_l = s.frame.to_local(s.wo);
  float u_lobe = rng.next_float();
  Vec2 u = rng.next_2d();
  if (!bsdf_sample(s.bsdf, wo_l, u_lobe, u, bs) || !(bs.pdf > 0)) return Rgb(0);
  const Rgb beta = bs.f * (std::fabs(bs.wi.z) / bs.pdf);
  const Vec3 wi = s.frame.to_world(bs.wi);
  Hit hit;
  if (!ctx.accel.intersect(spawn_ray(s.p, s.ng, wi, ctx.accel.ray_epsilon()), hit))
    return beta * ctx.lights.environment_radiance(wi);
  SurfaceInteraction si = ctx.accel.interaction(Ray{s.p, wi}, hit);
  uint32_t e = si.is_sphere ? ctx.lights.sphere_emitter(si.prim) : ctx.lights.triangle_emitter(si.geom, si.prim);
  return e == kNoEmitter ? Rgb(0) : beta * ctx.lights.emitted(e, si.ng, -wi);
}

}  // namespace rl
