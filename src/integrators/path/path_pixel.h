// The path tracer's per-path code (issue 16): one bounce of a path and the camera ray of a pixel
// sample, RESTIR_HD over device-shaped views, so that the CPU's wavefront path tracer and the CUDA
// backend's kernels run the same code (ARCHITECTURE.md, "Backends").
#pragma once
#include "core/rng.h"
#include "core/sampling.h"
#include "frame/direction_sampling.h"
#include "frame/options.h"
#include "frame/frame_world.h"
#include "frame/pixel_sampler.h"
#include "scene/camera.h"
#include "scene/lights_view.h"
#include "scene/ray_queries.h"
#include "scene/scene_view.h"

namespace rl {

// The state of one path between bounces: what pbrt-v4's PathIntegrator::Li keeps in locals, as a
// flat, trivially copyable record so that a wavefront loop can keep a buffer of them.
struct PathState {
  Ray ray;                   // the ray to trace next
  Rgb L{0}, beta{1};         // radiance so far, throughput
  Vec3 prev_p;               // the vertex `ray` left from
  float prev_pdf = 0;        // solid-angle pdf of the direction that produced `ray`
  bool specular = false;     // `ray` left a delta lobe
  int depth = 0;             // bounces so far
  Pcg32 rng;                 // the path's own random stream
};
// A next-event estimate waiting for its shadow ray: add `contribution` to L if `ray` is unoccluded.
struct PendingShadow {
  Ray ray;
  Rgb contribution{0};
  bool valid = false;
};

// Shadow ray from surface point p (geometric normal ng) to a light sample: toward its point, or
// unbounded toward the environment. Both next-event estimators (path tracer, ReSTIR GI) use it.
RESTIR_HD inline Ray shadow_ray_to_light(Vec3 p, Vec3 ng, const LightSample& ls, float eps) {
  return ls.distance >= kInfinity ? spawn_ray(p, ng, ls.wi, eps) : spawn_ray_to(p, ng, ls.position, ls.normal, eps);
}

RESTIR_HD inline float path_mis_weight(MisHeuristic h, float pa, float pb) {
  return h == MisHeuristic::power ? power_heuristic(pa, pb) : balance_heuristic(pa, pb);
}

// One bounce of the path tracer, given the closest hit of st.ray (null: it escaped): adds the
// emission it sees (MIS-weighted, Veach 1997 ch. 9), prepares next-event estimation in `shadow`
// (the caller traces its ray and adds its contribution if unoccluded), samples the next direction
// and applies Russian roulette (pbrt-v4 PathIntegrator::Li). false: the path ends (after `shadow`
// is resolved). The CPU's path_radiance and wavefront, and the CUDA kernels, all run this.
RESTIR_HD inline bool path_bounce(const PathWorld& w, const PathOptions& opt, PathState& st, const Hit* hit, PendingShadow& shadow,
                                  bool skip_first_emission = false) {
  const LightsView& lights = w.lights;
  const float eps = w.ray_epsilon;
  const bool nee = opt.nee && !lights.empty();
  const int depth = st.depth;
  shadow.valid = false;
  if (!hit) {
    if (depth == 0 && skip_first_emission) return false;
    const LightsView::EnvironmentValue env = lights.environment_value(st.ray.d);  // one texel lookup
    const Rgb Le = env.radiance;
    if (!is_black(Le)) {
      float mw = 1;
      if (depth > 0 && !st.specular && nee) mw = path_mis_weight(opt.mis, st.prev_pdf, env.pdf);
      st.L += st.beta * Le * mw;
    }
    return false;
  }
  const SurfaceInteraction si = surface_interaction(w.scene, st.ray, *hit);

  // Emission seen along the ray, MIS-weighted against light sampling from the previous vertex.
  const uint32_t emitter = si.is_sphere ? lights.sphere_emitter(si.prim) : lights.triangle_emitter(si.geom, si.prim);
  if (emitter != kNoEmitter && !(depth == 0 && skip_first_emission)) {
    const Rgb Le = lights.emitted(emitter, si.ng, -st.ray.d);
    if (!is_black(Le)) {
      float mw = 1;
      if (depth > 0 && !st.specular && nee) mw = path_mis_weight(opt.mis, st.prev_pdf, lights.pdf(emitter, st.prev_p, si.p, si.ng));
      st.L += st.beta * Le * mw;
    }
  }
  if (depth >= opt.max_depth) return false;

  const MaterialParams& mat = w.scene.materials[si.material];
  const Bsdf bsdf = make_bsdf(mat, material_reflectance(w.scene, mat, si.uv));
  const Frame frame = Frame::from_normal(si.ns);
  const Vec3 wo = frame.to_local(-st.ray.d);
  const bool delta = bsdf_is_delta(bsdf);
  Pcg32& rng = st.rng;

  // Next-event estimation: one light sample, MIS-weighted against BSDF sampling.
  if (nee && !delta) {
    LightSample ls;
    const float u_select = rng.next_float();
    const Vec2 u_light = rng.next_2d();
    if (lights.sample(si.p, u_select, u_light, ls) && ls.pdf > 0 && !is_black(ls.radiance)) {
      const Vec3 wi = frame.to_local(ls.wi);
      const Rgb f = bsdf_eval(bsdf, wo, wi) * std::fabs(wi.z);
      if (!is_black(f)) {
        const float mw = ls.is_delta ? 1.0f : path_mis_weight(opt.mis, ls.pdf, direction_pdf(bsdf, opt.bsdf_sampling, wo, wi));
        shadow.ray = shadow_ray_to_light(si.p, si.ng, ls, eps);
        shadow.contribution = st.beta * f * ls.radiance * (mw / ls.pdf);
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
  st.ray = spawn_ray(si.p, si.ng, frame.to_world(bs.wi), eps);
  st.depth = depth + 1;

  // Russian roulette (pbrt-v4): survive with probability max(beta) once past rr_min_depth.
  if (opt.russian_roulette && depth + 1 >= opt.rr_min_depth) {
    const float m = max_component(st.beta);
    if (m < 1) {
      const float q = std::max(0.0f, 1 - m);
      if (rng.next_float() < q) return false;
      st.beta /= 1 - q;
    }
  }
  return true;
}

// The path tracer's radiance along `ray` (pbrt-v4 PathIntegrator::Li): path_bounce until the path
// ends, each bounce's closest hit and shadow ray through `tracer` (di_pixel.h's Tracer). `first`,
// when not null, is the closest hit of `ray` the caller already has (*first invalid: it escaped).
// rng advances as the path draws from it. The CPU's path_radiance and ReSTIR GI's samples on either
// backend run this.
template <class Tracer>
RESTIR_HD Rgb path_radiance(const PathWorld& w, const Tracer& tracer, const PathOptions& opt, Ray ray, Pcg32& rng,
                               bool skip_first_emission = false, const Hit* first = nullptr) {
  PathState st;
  st.ray = ray;
  st.rng = rng;
  for (bool known = first != nullptr;; known = false) {
    Hit hit;
    bool found;
    if (known) {
      found = first->valid();
      if (found) hit = *first;
    } else {
      found = tracer.intersect(st.ray, hit);
    }
    PendingShadow shadow;
    const bool alive = path_bounce(w, opt, st, found ? &hit : nullptr, shadow, skip_first_emission);
    if (shadow.valid && !tracer.occluded(shadow.ray)) st.L += shadow.contribution;
    if (!alive) break;
  }
  rng = st.rng;
  return st.L;
}

// Path i of the wave that starts at (pixel, sample) index `begin`: its camera ray and random stream.
RESTIR_HD inline void start_path(const CameraSampling& cs, const PerspectiveCamera& camera, int frame, int width, uint32_t spp,
                                 size_t begin, PathState* paths, uint32_t* live, size_t i) {
  const size_t index = begin + i;
  const uint32_t pixel = uint32_t(index / spp), s = uint32_t(index % spp);
  const int x = int(pixel % uint32_t(width)), y = int(pixel / uint32_t(width));
  PathState& st = paths[i];
  st = PathState{};
  st.ray = camera_ray(cs, camera, x, y, frame, int(s));
  st.rng = make_rng(pixel, uint32_t(frame), RngPass::path, cs.seed, s);
  live[i] = uint32_t(i);
}

// The host's copies of the wavefront's two per-path loops on its widest instruction set
// (core/widest.h, path_tracer.cpp): start_path for paths [a, b) (the camera stage: 25% less time),
// and one bounce (path_bounce) of the live paths live[a..b) (the shading stage: 20% less time;
// Cornell box, 640x360, 4 paired runs).
void start_path_range(const CameraSampling& cs, const PerspectiveCamera& camera, int frame, int width, uint32_t spp, size_t begin,
                      PathState* paths, uint32_t* live, size_t a, size_t b);
void shade_paths(const PathWorld& world, const PathOptions& po, PathState* paths, const uint32_t* live, const Hit* hits,
                 PendingShadow* shadows, uint8_t* alive, size_t a, size_t b);

}  // namespace rl
