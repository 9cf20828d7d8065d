#include "integrators/di_sampling.h"

#include <algorithm>

#include "core/parallel.h"
#include "integrators/di_candidates.h"

namespace rl {

using di_detail::LightView;
using di_detail::di_value;

// The batch of light candidates on this machine's widest vectors: on x86-64 with GCC, one copy
// for AVX2 (x86-64-v3, 8 lanes) chosen at load time where the CPU has it, and the baseline SSE2
// copy (4 lanes) elsewhere. -ffp-contract=off (CMakeLists.txt) keeps both copies' arithmetic
// identical, so the machine does not change the image.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
[[gnu::flatten, gnu::target_clones("arch=x86-64-v3", "default")]]
#endif
uint32_t di_eval_light_candidates_host(const LightsView& lights, const GSurface& s, Vec3 wo_l, bool bsdf_pdfs,
                                       DiCandidateBatch& b) {
  return di_eval_light_candidates(lights, s, wo_l, bsdf_pdfs, b);
}

Rgb di_unshadowed(const Lights& lights, const GSurface& s, const LightPoint& y, float eps, Ray* shadow_ray) {
  return di_unshadowed(lights.view(), s, y, eps, shadow_ray);
}

// The host's view of these (one per call: LightsView is a handful of pointers).
namespace {
bool view_light(const Lights& lights, const GSurface& s, const LightPoint& y, LightView& v) {
  return di_detail::view_light(lights.view(), s, y, v);
}
Ray di_shadow_ray(const Lights& lights, const GSurface& s, const LightPoint& y, const LightView& v, float eps) {
  return di_detail::di_shadow_ray(lights.view(), s, y, v, eps);
}
float light_density(const Lights& lights, const GSurface& s, const LightPoint& y, const LightView& v) {
  return di_detail::light_density(lights.view(), s, y, v);
}
}  // namespace

float di_target(const RenderContext& ctx, const GSurface& s, const LightPoint& y, bool visibility) {
  return di_target(ctx, ctx.lights, s, y, visibility);
}

float di_target(const RenderContext& ctx, const Lights& lights, const GSurface& s, const LightPoint& y, bool visibility) {
  Ray shadow;
  float t = luminance(di_unshadowed(lights, s, y, ctx.accel.ray_epsilon(), visibility ? &shadow : nullptr));
  if (!(t > 0)) return 0;
  if (visibility && ctx.accel.occluded(shadow)) return 0;
  return t;
}

namespace {

// The initial resampling of one pixel (di_initial_reservoir): the two strategies' candidates
// streamed into one reservoir with their balance-heuristic resampling weights.
class InitialResampler {
 public:
  InitialResampler(const RenderContext& ctx, const GSurface& s, int light_candidates, int bsdf_candidates, bool visibility)
      : ctx_(ctx), s_(s), eps_(ctx.accel.ray_epsilon()), ml_(float(light_candidates)), mb_(float(bsdf_candidates)),
        // See weight(): without visibility in the target, a light candidate's BSDF density needs its shadow ray.
        bsdf_visibility_(!visibility && bsdf_candidates > 0), wo_l_(s.frame.to_local(s.wo)) {
    r_.confidence = float(light_candidates + bsdf_candidates);
  }
  void light_candidates(int count, Pcg32& rng, std::span<const LightTileEntry> tile, std::span<const EnvTileEntry> env_tile);
  void bsdf_candidates(int count, Pcg32& rng);
  DiReservoir& reservoir() { return r_; }

 private:
  // Resampling weight with the balance heuristic over the two strategies (Bitterli et al. 2020
  // eq. 4 with MIS; Veach 1997 eq. 9.10): target / (M_l p_light + M_b p_bsdf). A BSDF ray stops at
  // the first surface, so the BSDF strategy produces a light point only where it is visible from s.
  // With visibility in the target that is all that matters (occluded points have target 0). Without
  // it the target covers occluded points too, produced by light sampling alone: their BSDF density
  // is 0, which takes a shadow ray per light candidate. Counting it there (as before) left W short
  // on points occluded here and darkened the neighbours that reuse them where they are visible.
  // light_pdf: the light strategy's density when the caller has it (a light candidate), else < 0;
  // shadow_test: a light candidate whose BSDF density needs its visibility (above).
  float weight(const LightPoint& y, const LightView& v, float target, float light_pdf, bool shadow_test) const {
    if (!(target > 0)) return 0.0f;
    const float p_light = light_pdf >= 0 ? light_pdf : light_density(ctx_.lights, s_, y, v);
    float p_bsdf = 0;  // BSDF sampling never hits a point light
    if (mb_ > 0 && ctx_.lights.kind(y.emitter) != Lights::Kind::point) {
      p_bsdf = bsdf_pdf(s_.bsdf, wo_l_, v.wi_l) * v.g;
      if (shadow_test && bsdf_visibility_ && p_bsdf > 0 && ctx_.accel.occluded(di_shadow_ray(ctx_.lights, s_, y, v, eps_))) p_bsdf = 0;
    }
    return balance_weight(target, p_light, p_bsdf);
  }
  float balance_weight(float target, float p_light, float p_bsdf) const {
    const float den = ml_ * p_light + mb_ * p_bsdf;
    return den > 0 ? target / den : 0.0f;
  }
  void scalar_light_candidate(uint32_t e, float pmf, Vec2 u, float u_stream, std::span<const EnvTileEntry> env_tile);
  void stream_batch(const DiCandidateBatch& b, uint32_t scalar, uint32_t skip, const float* u_stream,
                    std::span<const EnvTileEntry> env_tile);

  const RenderContext& ctx_;
  const GSurface& s_;
  const float eps_, ml_, mb_;
  const bool bsdf_visibility_;
  const Vec3 wo_l_;
  DiReservoir r_;
};

// One light candidate evaluated on its own: the kinds the batch leaves (point lights, the
// environment, a receiver inside a sphere).
void InitialResampler::scalar_light_candidate(uint32_t e, float pmf, Vec2 u, float u_stream,
                                              std::span<const EnvTileEntry> env_tile) {
  if (!env_tile.empty() && e == ctx_.lights.environment_emitter()) {  // a presampled direction (LightTiles)
    const EnvTileEntry& en = env_tile[std::min(env_tile.size() - 1, size_t(u.x * float(env_tile.size())))];
    if (!(en.pdf > 0)) return;
    const LightPoint y{en.direction, e};
    LightView v;
    v.wi = en.direction, v.le = en.radiance, v.g = 1, v.wi_l = s_.frame.to_local(v.wi);
    const float t = is_black(v.le) ? 0.0f : luminance(di_value(s_, wo_l_, v));
    restir::stream(r_, y, t, weight(y, v, t, en.pdf * pmf, true), u_stream);  // the map's density x the pmf
    return;
  }
  LightSample ls;
  if (!ctx_.lights.sample_emitter(e, s_.p, u, ls)) return;
  const LightPoint y{ls.position, e};
  LightView v;
  const float t = view_light(ctx_.lights, s_, y, v) ? luminance(di_value(s_, wo_l_, v)) : 0.0f;
  // sample_emitter's solid-angle density times the selection pmf, in y's sample measure.
  const float light_pdf = ctx_.lights.kind(e) == Lights::Kind::point ? pmf : ls.pdf * pmf * v.g;
  restir::stream(r_, y, t, weight(y, v, t, light_pdf, true), u_stream);
}

// The light candidates, a batch at a time (di_candidates.h): their random numbers and emitters
// first, in the order one candidate at a time drew them, then the spheres and triangles in SIMD
// lanes, the other kinds one by one; then streamed in candidate order. The same samples, targets
// and weights as evaluating each in turn, bit for bit.
void InitialResampler::light_candidates(int count, Pcg32& rng, std::span<const LightTileEntry> tile,
                                        std::span<const EnvTileEntry> env_tile) {
  const size_t tile_size = tile.size();
  const LightEmitter* emitters = ctx_.lights.view().emitters;
  DiCandidateBatch b;
  float u_stream[kDiCandidateBatch];
  for (int base = 0; base < count; base += kDiCandidateBatch) {
    b.n = std::min(kDiCandidateBatch, count - base);
    uint32_t skip = 0;  // no emitter selected
    for (int i = 0; i < b.n; ++i) {
      const float u_select = rng.next_float();
      const Vec2 u = rng.next_2d();
      u_stream[i] = rng.next_float();
      b.ux[i] = u.x, b.uy[i] = u.y;
      if (tile_size > 0) {  // the emitter from the pixel's tile: marginally by the selection pmf
        const LightTileEntry& t = tile[std::min(tile_size - 1, size_t(u_select * float(tile_size)))];
        b.emitter[i] = t.emitter;
        b.pmf[i] = t.pmf;
      } else {
        b.emitter[i] = ctx_.lights.select_emitter(u_select, &b.pmf[i]);
      }
      if (b.emitter[i] == kNoEmitter) skip |= 1u << i, b.emitter[i] = 0;
      // The emitter records are read in the batch's gather; fetching them now overlaps the cache
      // misses with the rest of this loop (they were a sixth of the candidate stage).
      const char* record = reinterpret_cast<const char*>(emitters + b.emitter[i]);
      __builtin_prefetch(record);
      __builtin_prefetch(record + 64);
    }
    const uint32_t scalar = di_eval_light_candidates_host(ctx_.lights.view(), s_, wo_l_, mb_ > 0, b) & ~skip;
    stream_batch(b, scalar, skip, u_stream, env_tile);
  }
}

void InitialResampler::stream_batch(const DiCandidateBatch& b, uint32_t scalar, uint32_t skip, const float* u_stream,
                                    std::span<const EnvTileEntry> env_tile) {
  for (int i = 0; i < b.n; ++i) {
    if (skip & (1u << i)) continue;
    const uint32_t e = b.emitter[i];
    if (scalar & (1u << i)) {
      scalar_light_candidate(e, b.pmf[i], Vec2{b.ux[i], b.uy[i]}, u_stream[i], env_tile);
      continue;
    }
    if (!b.valid[i]) continue;
    const LightPoint y{Vec3{b.qx[i], b.qy[i], b.qz[i]}, e};
    float w = 0;  // weight(), with the batch's densities
    if (b.target[i] > 0) {
      float p_bsdf = mb_ > 0 ? b.bsdf_pdf[i] : 0.0f;
      if (bsdf_visibility_ && p_bsdf > 0) {
        LightView v;
        if (view_light(ctx_.lights, s_, y, v) && ctx_.accel.occluded(di_shadow_ray(ctx_.lights, s_, y, v, eps_))) p_bsdf = 0;
      }
      w = balance_weight(b.target[i], b.light_pdf[i], p_bsdf);
    }
    restir::stream(r_, y, b.target[i], w, u_stream[i]);
  }
}

void InitialResampler::bsdf_candidates(int count, Pcg32& rng) {
  for (int i = 0; i < count; ++i) {
    BsdfSample bs;
    float u_lobe = rng.next_float();
    Vec2 u = rng.next_2d();
    float u_stream = rng.next_float();
    if (!bsdf_sample(s_.bsdf, wo_l_, u_lobe, u, bs) || bs.is_delta || !(bs.pdf > 0)) continue;
    const Vec3 wi = s_.frame.to_world(bs.wi);
    Hit hit;
    LightPoint y;
    if (ctx_.accel.intersect(spawn_ray(s_.p, s_.ng, wi, eps_), hit)) {
      SurfaceInteraction si = ctx_.accel.interaction(Ray{s_.p, wi}, hit);
      y.emitter = si.is_sphere ? ctx_.lights.sphere_emitter(si.prim) : ctx_.lights.triangle_emitter(si.geom, si.prim);
      y.position = si.p;
    } else if (ctx_.lights.has_environment()) {
      y.emitter = ctx_.lights.environment_emitter();
      y.position = wi;
    }
    if (y.emitter == kNoEmitter) continue;
    LightView v;
    const float t = view_light(ctx_.lights, s_, y, v) ? luminance(di_value(s_, wo_l_, v)) : 0.0f;
    restir::stream(r_, y, t, weight(y, v, t, -1.0f, false), u_stream);
  }
}

}  // namespace

DiReservoir di_initial_reservoir(const RenderContext& ctx, const GSurface& s, int light_candidates, int bsdf_candidates,
                                 bool visibility, Pcg32& rng, std::span<const LightTileEntry> tile,
                                 std::span<const EnvTileEntry> env_tile) {
  InitialResampler ris(ctx, s, light_candidates, bsdf_candidates, visibility);
  DiReservoir& r = ris.reservoir();
  if (!s.valid || ctx.lights.empty() || bsdf_is_delta(s.bsdf)) return r;
  ris.light_candidates(light_candidates, rng, tile, env_tile);
  ris.bsdf_candidates(bsdf_candidates, rng);
  restir::finalize(r);
  if (visibility && r.has_sample() && !(di_target(ctx, s, r.sample, true) > 0)) {  // visibility reuse
    r.ucw = 0;
    r.target = 0;
  }
  return r;
}

void LightTiles::build(const Lights& lights, int count, int size, uint32_t frame, uint64_t seed, uint32_t chain, int env_size) {
  count_ = lights.empty() ? 0 : count;
  size_ = size;
  env_size_ = lights.has_environment() ? std::max(env_size, 0) : 0;
  entries_.resize(size_t(std::max(count_, 0)) * size_t(std::max(size_, 0)));
  env_entries_.resize(size_t(std::max(count_, 0)) * size_t(env_size_));
  if (count_ <= 0 || size_ <= 0) return;
  const uint32_t env = lights.environment_emitter();
  parallel_for(count_, [&](int t) {  // one stream per tile: the same tiles whatever the thread count
    Pcg32 rng = make_rng(uint32_t(t), frame, RngPass::light_tiles, seed, chain);
    for (int i = 0; i < size_; ++i) {
      LightTileEntry& en = entries_[size_t(t) * size_t(size_) + size_t(i)];
      en.emitter = lights.select_emitter(rng.next_float(), &en.pmf);
    }
    // The environment's directions, drawn after the emitters from the same stream (which leaves
    // the emitter entries as they were without them). The environment samples no receiver point.
    for (int i = 0; i < env_size_; ++i) {
      EnvTileEntry& en = env_entries_[size_t(t) * size_t(env_size_) + size_t(i)];
      LightSample ls;
      en = lights.sample_emitter(env, Vec3(0), rng.next_2d(), ls) ? EnvTileEntry{ls.wi, ls.radiance, ls.pdf} : EnvTileEntry{};
    }
  });
}

size_t LightTiles::tile_index(int x, int y, int width, uint32_t frame, uint64_t seed, uint32_t chain) const {
  const int blocks_x = (width + kBlockPixels - 1) / kBlockPixels;
  const uint32_t block = uint32_t((y / kBlockPixels) * blocks_x + x / kBlockPixels);
  Pcg32 rng = make_rng(block, frame, RngPass::light_tiles, seed, chain + 0x9e3779b9u);
  return std::min(size_t(count_) - 1, size_t(rng.next_float() * float(count_)));
}

std::span<const LightTileEntry> LightTiles::tile_of(int x, int y, int width, uint32_t frame, uint64_t seed,
                                                     uint32_t chain) const {
  if (count_ <= 0 || size_ <= 0) return {};
  return {entries_.data() + tile_index(x, y, width, frame, seed, chain) * size_t(size_), size_t(size_)};
}

std::span<const EnvTileEntry> LightTiles::env_tile_of(int x, int y, int width, uint32_t frame, uint64_t seed,
                                                      uint32_t chain) const {
  if (count_ <= 0 || size_ <= 0 || env_size_ <= 0) return {};
  return {env_entries_.data() + tile_index(x, y, width, frame, seed, chain) * size_t(env_size_), size_t(env_size_)};
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
