// ReSTIR DI's per-pixel stages: the initial resampling, the target function, the reuse bridge and
// the shading, RESTIR_HD over a FrameWorld and its Tracer (frame_world.h), so that every backend
// runs one implementation of every weight (EmbreeTracer on the CPU, BvhTracer on the others).
// A DI sample is a point on an emitter (area measure), a direction of the environment (solid
// angle) or a delta light -- point, spot or distant -- (counting measure) (Bitterli et al. 2020, §3-4). These measures do not
// depend on the shading point, so the shift between pixels is the identity with jacobian 1 and a
// reservoir can be reused as is.
#pragma once
#include "integrators/restir_di/di_candidates.h"
#include "integrators/restir_di/di_kernel.h"
#include "integrators/path/path_pixel.h"
#include "frame/frame_world.h"
#include "frame/reuse_pixel.h"
#include "restir/reservoir.h"

namespace rl {

using DiReservoir = restir::Reservoir<LightPoint>;
// RTXDI's packed DI reservoir is 32 bytes (issue 9: ours must be no larger).
static_assert(sizeof(DiReservoir) <= 32, "ReSTIR DI's reservoir outgrew RTXDI's 32 bytes");

// di_eval_light_candidates compiled for the host CPU's widest vectors (light_tiles.cpp).
uint32_t di_eval_light_candidates_host(const LightsView& lights, const GSurface& s, Vec3 wo_l, bool bsdf_pdfs,
                                       DiCandidateBatch& b);

// The emitter a ray from s in direction wi reaches (kNoEmitter: a non-emitting surface, or an
// escape without environment), and the light point there.
template <class Tracer>
RESTIR_HD inline LightPoint di_trace_to_light(const PathWorld& w, const Tracer& tracer, const GSurface& s, Vec3 wi) {
  LightPoint y;
  Hit hit;
  if (tracer.intersect(spawn_ray(s.p, s.ng, wi, w.ray_epsilon), hit)) {
    const SurfaceInteraction si = surface_interaction(w.scene, Ray{s.p, wi}, hit);
    y.emitter = w.lights.emitter_at(si);
    y.position = si.p;
  } else if (w.lights.has_environment()) {
    y.emitter = w.lights.environment_emitter();
    y.position = wi;
  }
  return y;
}

// Target function p̂ = luminance of the unshadowed integrand di_unshadowed (di_kernel.h; times
// visibility when `visibility`), with `lights` (the world's, or an animated scene's previous ones).
template <class Tracer>
RESTIR_HD inline float di_target(const LightsView& lights, float eps, const Tracer& tracer, const GSurface& s, const LightPoint& y,
                                    bool visibility) {
  Ray shadow;
  const float t = luminance(di_unshadowed(lights, s, y, eps, visibility ? &shadow : nullptr));
  if (!(t > 0)) return 0;
  if (visibility && tracer.occluded(shadow)) return 0;
  return t;
}

// The initial resampling of one pixel (di_initial_reservoir, di_sampling.h): the two strategies'
// candidates streamed into one reservoir with their balance-heuristic resampling weights.
template <class Tracer>
class DiInitialResampler {
 public:
  RESTIR_HD DiInitialResampler(const PathWorld& w, const Tracer& tracer, const GSurface& s, int light_candidates, int bsdf_candidates,
                               bool visibility)
      : w_(w), L_(w.lights), tracer_(tracer), s_(s), eps_(w.ray_epsilon), ml_(float(light_candidates)), mb_(float(bsdf_candidates)),
        // See weight(): without visibility in the target, a light candidate's BSDF density needs its shadow ray.
        bsdf_visibility_(!visibility && bsdf_candidates > 0), frame_(s.frame()), wo_l_(frame_.to_local(s.wo)) {
    r_.confidence = float(light_candidates + bsdf_candidates);
  }
  RESTIR_HD void light_candidates(int count, Pcg32& rng, const LightTileView& tile);
  RESTIR_HD void bsdf_candidates(int count, Pcg32& rng);
  RESTIR_HD DiReservoir& reservoir() { return r_; }

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
  RESTIR_HD float weight(const LightPoint& y, const di_detail::LightView& v, float target, float light_pdf, bool shadow_test) const {
    if (!(target > 0)) return 0.0f;
    const float p_light = light_pdf >= 0 ? light_pdf : di_detail::light_density(L_, s_, y, v);
    float p_bsdf = 0;  // BSDF sampling never hits a delta light
    if (mb_ > 0 && !L_.is_delta(y.emitter)) {
      p_bsdf = bsdf_pdf(s_.bsdf, wo_l_, v.wi_l) * v.g;
      if (shadow_test && bsdf_visibility_ && p_bsdf > 0 && tracer_.occluded(di_detail::di_shadow_ray(L_, s_, y, v, eps_))) p_bsdf = 0;
    }
    return balance_weight(target, p_light, p_bsdf);
  }
  RESTIR_HD float balance_weight(float target, float p_light, float p_bsdf) const {
    const float den = ml_ * p_light + mb_ * p_bsdf;
    return den > 0 ? target / den : 0.0f;
  }
  RESTIR_HD uint32_t select(float u_select, const LightTileView& tile, float& pmf) const {
    if (tile.light_count > 0) {  // the emitter from the pixel's tile: marginally by the selection pmf
      const LightTileEntry& t = tile.lights[LightTileView::pick(u_select, tile.light_count)];
      pmf = t.pmf;
      return t.emitter;
    }
    return L_.select_emitter(u_select, &pmf);
  }
  RESTIR_HD void scalar_light_candidate(uint32_t e, float pmf, Vec2 u, float u_stream, const LightTileView& tile);
  RESTIR_HD void stream_batch(const DiCandidateBatch& b, uint32_t scalar, uint32_t skip, const float* u_stream, const LightTileView& tile);

  const PathWorld& w_;
  const LightsView& L_;
  const Tracer& tracer_;
  const GSurface& s_;
  const float eps_, ml_, mb_;
  const bool bsdf_visibility_;
  const Frame frame_;  // s_.frame(), built once for all the pixel's candidates
  const Vec3 wo_l_;
  DiReservoir r_;
};

// One light candidate evaluated on its own: on the GPU every candidate (a thread is already one
// lane of a SIMT vector), on the CPU the kinds the batch leaves (delta lights, the environment, a
// receiver inside a sphere).
template <class Tracer>
RESTIR_HD void DiInitialResampler<Tracer>::scalar_light_candidate(uint32_t e, float pmf, Vec2 u, float u_stream, const LightTileView& tile) {
  using di_detail::LightView;
  if (tile.env_count > 0 && e == L_.environment_emitter()) {  // a presampled direction (LightTiles)
    const EnvTileEntry& en = tile.env[LightTileView::pick(u.x, tile.env_count)];
    if (!(en.pdf > 0)) return;
    const LightPoint y{en.direction, e};
    LightView v;
    v.wi = en.direction, v.le = en.radiance, v.g = 1, v.wi_l = frame_.to_local(v.wi);
    const float t = is_black(v.le) ? 0.0f : luminance(di_detail::di_value(s_, wo_l_, v));
    restir::stream(r_, y, t, weight(y, v, t, en.pdf * pmf, true), u_stream);  // the map's density x the pmf
    return;
  }
  LightSample ls;
  if (!L_.sample_emitter(e, s_.p, u, ls)) return;
  const LightPoint y{ls.position, e};
  LightView v;
  const float t = di_detail::view_light(L_, s_, y, v) ? luminance(di_detail::di_value(s_, wo_l_, v)) : 0.0f;
  // sample_emitter's solid-angle density times the selection pmf, in y's sample measure.
  const float light_pdf = L_.is_delta(e) ? pmf : ls.pdf * pmf * v.g;
  restir::stream(r_, y, t, weight(y, v, t, light_pdf, true), u_stream);
}

// The light candidates. Each draws u_select, u (2D) and u_stream from rng in turn. On the CPU a
// batch at a time (di_candidates.h): their random numbers and emitters first, in that order, then
// the spheres and triangles in SIMD lanes, the other kinds one by one; then streamed in candidate
// order -- the same samples, targets and weights as one at a time, bit for bit, which is how the GPU
// evaluates them.
template <class Tracer>
RESTIR_HD void DiInitialResampler<Tracer>::light_candidates(int count, Pcg32& rng, const LightTileView& tile) {
#ifdef __CUDA_ARCH__
  for (int i = 0; i < count; ++i) {
    const float u_select = rng.next_float();
    const Vec2 u = rng.next_2d();
    const float u_stream = rng.next_float();
    float pmf = 0;
    const uint32_t e = select(u_select, tile, pmf);
    if (e != kNoEmitter) scalar_light_candidate(e, pmf, u, u_stream, tile);
  }
#else
  DiCandidateBatch b;
  float u_stream[kDiCandidateBatch];
  for (int base = 0; base < count; base += kDiCandidateBatch) {
    b.n = count - base < kDiCandidateBatch ? count - base : kDiCandidateBatch;
    uint32_t skip = 0;  // no emitter selected
    for (int i = 0; i < b.n; ++i) {
      const float u_select = rng.next_float();
      const Vec2 u = rng.next_2d();
      u_stream[i] = rng.next_float();
      b.ux[i] = u.x, b.uy[i] = u.y;
      b.emitter[i] = select(u_select, tile, b.pmf[i]);
      if (b.emitter[i] == kNoEmitter) skip |= 1u << i, b.emitter[i] = 0;
      // The emitter records are read in the batch's gather; fetching them now overlaps the cache
      // misses with the rest of this loop (they were a sixth of the candidate stage).
      const char* record = reinterpret_cast<const char*>(L_.emitters + b.emitter[i]);
      prefetch_line(record);
      prefetch_line(record + 64);
    }
    const uint32_t scalar = di_eval_light_candidates_host(L_, s_, wo_l_, mb_ > 0, b) & ~skip;
    stream_batch(b, scalar, skip, u_stream, tile);
  }
#endif
}

template <class Tracer>
RESTIR_HD void DiInitialResampler<Tracer>::stream_batch(const DiCandidateBatch& b, uint32_t scalar, uint32_t skip, const float* u_stream,
                                                        const LightTileView& tile) {
  for (int i = 0; i < b.n; ++i) {
    if (skip & (1u << i)) continue;
    const uint32_t e = b.emitter[i];
    if (scalar & (1u << i)) {
      scalar_light_candidate(e, b.pmf[i], Vec2{b.ux[i], b.uy[i]}, u_stream[i], tile);
      continue;
    }
    if (!b.valid[i]) continue;
    const LightPoint y{Vec3{b.qx[i], b.qy[i], b.qz[i]}, e};
    float w = 0;  // weight(), with the batch's densities
    if (b.target[i] > 0) {
      float p_bsdf = mb_ > 0 ? b.bsdf_pdf[i] : 0.0f;
      if (bsdf_visibility_ && p_bsdf > 0) {
        di_detail::LightView v;
        if (di_detail::view_light(L_, s_, y, v) && tracer_.occluded(di_detail::di_shadow_ray(L_, s_, y, v, eps_))) p_bsdf = 0;
      }
      w = balance_weight(b.target[i], b.light_pdf[i], p_bsdf);
    }
    restir::stream(r_, y, b.target[i], w, u_stream[i]);
  }
}

template <class Tracer>
RESTIR_HD void DiInitialResampler<Tracer>::bsdf_candidates(int count, Pcg32& rng) {
  for (int i = 0; i < count; ++i) {
    BsdfSample bs;
    const float u_lobe = rng.next_float();
    const Vec2 u = rng.next_2d();
    const float u_stream = rng.next_float();
    if (!bsdf_sample(s_.bsdf, wo_l_, u_lobe, u, bs) || bs.is_delta || !(bs.pdf > 0)) continue;
    const LightPoint y = di_trace_to_light(w_, tracer_, s_, frame_.to_world(bs.wi));
    if (y.emitter == kNoEmitter) continue;
    di_detail::LightView v;
    const float t = di_detail::view_light(L_, s_, y, v) ? luminance(di_detail::di_value(s_, wo_l_, v)) : 0.0f;
    restir::stream(r_, y, t, weight(y, v, t, -1.0f, false), u_stream);
  }
}

// Initial resampling (Talbot et al. 2005 RIS with the balance heuristic over the two strategies):
// light_candidates from the light sampler (emitter by the selection pmf -- from the pixel's tile
// when there is one, see LightTiles -- then a point on it for this surface, sample_emitter: the
// visible cap of a sphere, uniform by area on triangles) and bsdf_candidates by tracing BSDF
// samples to emitters, each with resampling weight p̂(x) / (M_l p_l(x) + M_b p_b(x)) (pdfs in the
// sample measure). Confidence = M_l + M_b. With `visibility`, the chosen sample is shadow-tested
// and its weight zeroed if occluded, making the reservoir's target p̂·V (Bitterli et al. 2020, §4.4
// "visibility reuse"). A light candidate that picks the environment takes its direction from the
// tile's environment directions when there are some, instead of sampling the map.
template <class Tracer>
RESTIR_HD inline DiReservoir di_initial_reservoir(const PathWorld& w, const Tracer& tracer, const GSurface& s, int light_candidates,
                                                     int bsdf_candidates, bool visibility, Pcg32& rng, const LightTileView& tile) {
  DiInitialResampler<Tracer> ris(w, tracer, s, light_candidates, bsdf_candidates, visibility);
  DiReservoir& r = ris.reservoir();
  if (!s.valid || w.lights.empty() || bsdf_is_delta(s.bsdf)) return r;
  ris.light_candidates(light_candidates, rng, tile);
  ris.bsdf_candidates(bsdf_candidates, rng);
  restir::finalize(r);
  if (visibility && r.has_sample() && !(di_target(w.lights, w.ray_epsilon, tracer, s, r.sample, true) > 0)) {  // visibility reuse
    r.ucw = 0;
    r.target = 0;
  }
  return r;
}

// Direct light through a delta lobe (mirror, smooth glass, a smooth coat), which resampling cannot
// handle: follows the delta direction and returns the throughput-weighted emission it sees. A delta
// BSDF's lobes are sampled (reflection or refraction); the delta lobe of a BSDF that mixes one with
// non-delta lobes (coated diffuse; the reservoir covers the others) is followed whole, with its
// weight (bsdf_delta_lobe): no lobe-choice noise.
template <class Tracer>
RESTIR_HD inline Rgb di_specular(const PathWorld& w, const Tracer& tracer, const GSurface& s, Pcg32& rng) {
  BsdfSample bs;
  const Frame shading = s.frame();
  const Vec3 wo_l = shading.to_local(s.wo);
  const float u_lobe = rng.next_float();
  const Vec2 u = rng.next_2d();
  const bool ok = bsdf_is_delta(s.bsdf) ? bsdf_sample(s.bsdf, wo_l, u_lobe, u, bs) : bsdf_delta_lobe(s.bsdf, wo_l, bs);
  if (!ok || !(bs.pdf > 0)) return Rgb(0);
  const Rgb beta = bs.f * (std::fabs(bs.wi.z) / bs.pdf);
  const Vec3 wi = shading.to_world(bs.wi);
  Hit hit;
  if (!tracer.intersect(spawn_ray(s.p, s.ng, wi, w.ray_epsilon), hit)) return beta * w.lights.environment_radiance(wi);
  const SurfaceInteraction si = surface_interaction(w.scene, Ray{s.p, wi}, hit);
  const uint32_t e = w.lights.emitter_at(si);
  return e == kNoEmitter ? Rgb(0) : beta * w.lights.emitted(e, si.ng, -wi);
}

// The bridge of mis.h for DI: the identity shift (all domains share the emitters' area measure),
// targets evaluated at each domain's own primary surface.
// In an animated scene the temporal pass's history (domain 1) lives in the previous frame: its
// samples move with their emitters into this frame (LightsView::follow: rigid motion, Jacobian 1 in
// area measure), and its target is the previous frame's -- the point carried back, the previous
// lights' emission (a light switched on since has none there). That keeps the history's MIS weight
// at 0 wherever the history could not have produced a sample (GRIS, Lin et al. 2022, sec. 5: the
// weights must vanish outside each domain's support), e.g. where a light moved into view;
// evaluating it with this frame's lights instead left -20 to -40 % on the dynamic room's glossy
// block (di.history_scene = current keeps that shortcut, named and measured as biased).
// Visibility in the history's target is tested in the previous frame's BVH (FrameWorld's previous
// world, kept by the renderer when the target includes visibility): the history only holds samples
// that were visible a frame earlier, so near a moving occluder's shadow this frame's BVH would give
// it the wrong support.
template <class Tracer>
struct DiBridges;

// Queued: the bridge of a queued reuse pass (ray_slots.h), whose shadow rays go through cursor; the
// inline pass's bridge (false) is a type of its own, so its code is what it was before queues.
template <class Tracer, bool Queued = false>
struct DiBridge {
  const DiBridges<Tracer>* b;
  SurfaceList surfaces;  // surfaces[i] = domain i's surface, 0 = canonical
  bool temporal;                    // domain 1 is the previous frame
  RayCursor* cursor;                // Queued: the pixel's slots
  RESTIR_HD bool history_lights() const { return temporal && b->fw.has_previous_lights; }
  RESTIR_HD bool history_scene() const { return temporal && b->fw.has_previous && !b->history_visibility_now; }
  RESTIR_HD bool shift_to_canonical(int i, const LightPoint& y, LightPoint& x, float& jacobian) const {
    x = y;
    jacobian = 1;
    Vec3 normal;  // follow's; a LightPoint derives its normal from its emitter
    if (i == 1 && history_lights()) return b->fw.world.lights.follow(y.emitter, b->fw.previous_lights, x.position, normal);
    return true;
  }
  // A reservoir's target is di_target at its own surface with the canonical visibility flag: the
  // canonical one always; another domain's (identity shift) when the other domains' targets use the
  // same flag and the same scene: a spatial neighbour of this frame, or the history of a static
  // scene (computed last frame at surfaces[1], in the same scene and lights).
  RESTIR_HD bool stored_target_valid(int i) const {
    return i == 0 || (b->canonical_visibility == b->other_visibility && (!temporal || !b->fw.animated));
  }
  // F(x), RGB, at the canonical surface (RGB resampling weights, mis.h; di.rgb_weights): the
  // unshadowed value. combine() asks it only for inputs with a positive target, and with
  // di.visibility_reuse (checked by the options) that target includes V, so V = 1 there: F needs no
  // shadow ray.
  RESTIR_HD Rgb color(const LightPoint& x) const {
    return di_unshadowed(b->fw.world.lights, surfaces[0], x, b->fw.world.ray_epsilon, nullptr);
  }
  RESTIR_HD float target_from(int i, const LightPoint& x) const {
    const FrameWorld<Tracer>& fw = b->fw;
    const bool lights = history_lights(), scene = history_scene();
    if (i == 1 && b->history_in_previous && (lights || scene)) {
      LightPoint back = x;  // where x was one frame earlier
      Vec3 normal;
      if (lights && !fw.previous_lights.follow(x.emitter, fw.world.lights, back.position, normal)) return 0;
      const LightsView& then = lights ? fw.previous_lights : fw.world.lights;
      if (scene)  // not queued: the queue holds this frame's rays
        return di_target(then, fw.previous_world.ray_epsilon, pass_tracer<Queued>(fw.previous_tracer, nullptr), surfaces[1], back,
                         b->other_visibility);
      return di_target(then, fw.world.ray_epsilon, pass_tracer<Queued>(fw.tracer, cursor), surfaces[1], back, b->other_visibility);
    }
    return di_target(fw.world.lights, fw.world.ray_epsilon, pass_tracer<Queued>(fw.tracer, cursor), surfaces[i], x,
                     i == 0 ? b->canonical_visibility : b->other_visibility);
  }
};

// The bridges of one frame, made per pixel by the reuse stages (reservoir_chain.h).
template <class Tracer>
struct DiBridges {
  FrameWorld<Tracer> fw;
  bool canonical_visibility;    // the canonical target includes visibility (di.visibility_reuse)
  bool other_visibility;        // other domains' targets include visibility (... and di.neighbor_visibility)
  bool history_in_previous;     // di.history_scene = previous
  bool history_visibility_now;  // a planted bias (planted_bias.h): the history's visibility in this frame's BVH
  RESTIR_HD DiBridge<Tracer> operator()(const SurfaceList& surfaces, int, bool temporal) const { return {this, surfaces, temporal, nullptr}; }
  RESTIR_HD DiBridge<Tracer, true> operator()(const SurfaceList& surfaces, int, bool temporal, RayCursor* cursor) const {
    return {this, surfaces, temporal, cursor};
  }
};

// The final shading of a pixel: f(y) W, with visibility traced unless the target already included
// it, or with di.rgb_weights `color`, the last spatial round's Σ m_i F(Y_i) W_i (mis.h; its inputs'
// visibility is in their targets); a delta lobe's direct light through di_specular (alone for a
// delta BSDF, added for a mixed one); emission and background as seen.
template <class Tracer>
RESTIR_HD inline Rgb di_shade(const PathWorld& w, const Tracer& tracer, const GSurface& sf, const DiReservoir& r, bool visibility_reuse,
                              uint32_t pixel, uint32_t frame, uint64_t seed, uint32_t chain, const Rgb* color = nullptr) {
  Rgb L = sf.le;
  if (!sf.valid) return L;
  if (bsdf_has_delta(sf.bsdf)) {
    Pcg32 rng = make_rng(pixel, frame, RngPass::misc, seed, chain);
    L += di_specular(w, tracer, sf, rng);
  }
  if (!bsdf_is_delta(sf.bsdf) && r.has_sample() && color) {
    L += *color;
  } else if (!bsdf_is_delta(sf.bsdf) && r.has_sample()) {
    Ray shadow;
    Rgb contrib = di_unshadowed(w.lights, sf, r.sample, w.ray_epsilon, &shadow) * r.ucw;
    if (!visibility_reuse && tracer.occluded(shadow)) contrib = Rgb(0);
    L += contrib;
  }
  mark_non_finite(r, L);
  return L;
}

}  // namespace rl
