// ReSTIR GI's per-pixel pieces (restir_gi_frame.h documents the method), RESTIR_HD over a
// FrameWorld and its Tracer (frame_world.h): the sample, its integrand and target, the
// reconnection shift's bridge, the initial sample and the direct light, one implementation for
// every backend.
#pragma once
#include "frame/gbuffer.h"
#include "integrators/path/path_pixel.h"
#include "frame/frame_world.h"
#include "frame/reuse_pixel.h"
#include "restir/reservoir.h"
#include "restir/shift.h"

namespace rl {

struct GiSample {
  Vec3 position;      // x_s, or the direction when the ray escaped to the environment
  Vec3 normal;        // geometric normal at x_s
  bool infinite = false;
  Rgb radiance{0};    // reflected L_o(x_s -> visible point), estimated by a path from x_s
  uint32_t geom = kInvalidId, prim = kInvalidId;  // the surface of x_s (its animation moves it)
  Pcg32 suffix;       // the random stream of the path that estimated `radiance` (replayed across frames)
};
using GiReservoir = restir::Reservoir<GiSample>;
// The sample's identity for the duplication map (reservoir_chain.h): reconnection keeps x_s.
RESTIR_HD inline uint64_t duplicate_key(const GiSample& x) { return hash_point(x.position, x.prim); }

// f_s(wo, wi) |cos| L_o at visible surface s for sample x (no visibility).
RESTIR_HD inline Rgb gi_integrand(const GSurface& s, const GiSample& x) {
  if (!s.valid) return Rgb(0);
  Vec3 wi = x.position;
  if (!x.infinite) {
    const Vec3 d = x.position - s.p;
    const float len = length(d);
    if (!(len > 0)) return Rgb(0);
    wi = d / len;
  }
  const Frame shading = s.frame();
  const Vec3 wo_l = shading.to_local(s.wo), wi_l = shading.to_local(wi);
  const Rgb v = bsdf_eval(s.bsdf, wo_l, wi_l) * std::fabs(wi_l.z) * x.radiance;
  return is_finite(v) ? max(v, Rgb(0)) : v;  // non-finite: reported by the render driver, never hidden
}

// The target: luminance of the integrand (gi.target = contribution) or of the cached radiance
// (radiance), times visibility of x_s from s when asked.
template <class Tracer>
RESTIR_HD float gi_target(const PathWorld& w, const Tracer& tracer, GiTarget kind, const GSurface& s, const GiSample& x,
                             bool visibility) {
  const Rgb v = gi_integrand(s, x);
  if (is_black(v)) return 0;
  if (visibility) {
    const float eps = w.ray_epsilon;
    const Ray r = x.infinite ? spawn_ray(s.p, s.ng, x.position, eps) : spawn_ray_to(s.p, s.ng, x.position, x.normal, eps);
    if (tracer.occluded(r)) return 0;
  }
  return luminance(kind == GiTarget::radiance ? x.radiance : v);
}

// Solid angle at `from` -> at `to` for the same sample point (1 for the environment; ReSTIR GI eq. 11).
RESTIR_HD inline float gi_jacobian(const GiSample& x, Vec3 from, Vec3 to) {
  return x.infinite ? 1.0f : restir::reconnection_jacobian(from, to, x.position, x.normal);
}

// The animation moving x_s's surface (-1: none).
RESTIR_HD inline int gi_animation_of(const SceneView& scene, const GiSample& x) {
  if (x.infinite) return -1;
  if (x.geom < scene.mesh_count) return scene.meshes[x.geom].animation;
  if (x.geom == scene.mesh_count && x.prim < scene.sphere_count) return scene.spheres[x.prim].animation;
  return -1;
}

// x carried by a rigid motion per animation (motion[a], count of them), its radiance not yet
// re-estimated.
RESTIR_HD inline GiSample gi_carried(const SceneView& scene, const Mat4* motion, uint32_t count, const GiSample& x) {
  GiSample y = x;
  const int a = gi_animation_of(scene, x);
  if (a >= 0 && uint32_t(a) < count) {
    y.position = motion[a].apply_point(x.position);
    y.normal = normalize(motion[a].apply_vector(x.normal));
  }
  return y;
}

// x with its radiance re-estimated in world w as seen from s: x's path stream replayed from x_s
// (0 where s does not see x_s). The visibility test comes first: it spares the path.
template <class Tracer>
RESTIR_HD GiSample gi_replayed(const PathWorld& w, const Tracer& tracer, const PathOptions& path, const GSurface& s, GiSample x) {
  const float eps = w.ray_epsilon;
  const Ray shadow = x.infinite ? spawn_ray(s.p, s.ng, x.position, eps) : spawn_ray_to(s.p, s.ng, x.position, x.normal, eps);
  x.radiance = Rgb(0);
  if (!s.valid || tracer.occluded(shadow)) return x;
  const Vec3 dir = x.infinite ? x.position : normalize(x.position - s.p);
  Pcg32 stream = x.suffix;
  x.radiance = path_radiance(w, tracer, path, spawn_ray(s.p, s.ng, dir, eps), stream, /*skip_first_emission=*/true);
  return x;
}

// The bridge of mis.h for GI: the reconnection shift (x_s kept, its cached radiance with it) and
// each domain's target at its own visible point.
// Temporal reuse in an animated scene (FrameWorld's previous world kept): domain 1 is the previous
// frame, whose cached radiance belongs to that frame's scene (see restir_gi.cpp): its shift carries
// x_s with its object's rigid motion and re-estimates L_o by replaying the sample's stream in this
// frame's scene (random replay of the suffix, GRIS §6.1: the identity in primary sample space,
// Jacobian 1); the reconnection Jacobian uses x_s's geometry in each frame (restir/shift.h). For
// the MIS weights, this frame's samples are carried back and replayed in the previous frame's
// scene and BVH, so that each frame's target is its own scene's, as GRIS requires.
template <class Tracer>
struct GiBridges;

// Queued: the bridge of a queued reuse pass (ray_slots.h; see DiBridge).
template <class Tracer, bool Queued = false>
struct GiBridge {
  const GiBridges<Tracer>* b;
  SurfaceList surfaces;  // surfaces[i] = domain i's visible point, 0 = canonical
  bool temporal;
  RayCursor* cursor;  // Queued: the pixel's slots
  // Domain 1 is another frame's, replayed across the frames (an animated scene's history).
  RESTIR_HD bool across_frames() const { return temporal && b->fw.has_previous && b->replay_history; }
  // Another domain's stored target is p̂_i(y) at its own visible point, visibility included, and
  // the shift keeps x = y with |∂T_{0→i}/∂x| = 1 / |∂T_{i→0}/∂y| (ReSTIR GI eq. 11 both ways). So
  // combine() reads p̂_i(y) / jacobian (mis.h) instead of tracing domain i's shadow ray to x again
  // -- except for an animated scene's history, whose stored target was computed in the other
  // frame's scene and whose shift is a replay between frames.
  RESTIR_HD bool stored_target_valid(int i) const { return i > 0 && !(i == 1 && temporal && b->fw.animated); }
  RESTIR_HD bool shift_to_canonical(int i, const GiSample& y, GiSample& x, float& jacobian) const {
    const FrameWorld<Tracer>& fw = b->fw;
    if (i == 1 && across_frames()) {
      x = gi_replayed(fw.world, pass_tracer<Queued>(fw.tracer, cursor), b->path, surfaces[0],
                      gi_carried(fw.world.scene, fw.forward, fw.animation_count, y));
      jacobian = x.infinite ? 1.0f
                            : restir::moved_reconnection_jacobian(surfaces.point(1), y.position, y.normal, surfaces.point(0), x.position,
                                                                  x.normal);
      return jacobian > 0;
    }
    x = y;
    jacobian = gi_jacobian(y, surfaces.point(i), surfaces.point(0));
    return jacobian > 0;
  }
  RESTIR_HD float target_from(int i, const GiSample& x) const {
    const FrameWorld<Tracer>& fw = b->fw;
    if (i == 1 && across_frames()) {
      const auto& previous = pass_tracer<Queued>(fw.previous_tracer, nullptr);  // not queued: the queue holds this frame's rays
      const GiSample back = gi_replayed(fw.previous_world, previous, b->path, surfaces[1],
                                        gi_carried(fw.world.scene, fw.back, fw.animation_count, x));
      const float t = gi_target(fw.previous_world, previous, b->kind, surfaces[1], back, false);  // visibility: in gi_replayed
      return x.infinite ? t
                        : t * restir::moved_reconnection_jacobian(surfaces.point(0), x.position, x.normal, surfaces.point(1), back.position,
                                                                  back.normal);
    }
    const float t = gi_target(fw.world, pass_tracer<Queued>(fw.tracer, cursor), b->kind, surfaces[i], x, true);
    return i == 0 ? t : t * gi_jacobian(x, surfaces.point(0), surfaces.point(i));
  }
};

// The bridges of one frame, made per pixel by the reuse stages (reservoir_chain.h).
template <class Tracer>
struct GiBridges {
  FrameWorld<Tracer> fw;
  GiTarget kind;
  PathOptions path;     // the sample's path: path.max_depth - 1 bounces
  bool replay_history;  // false: a planted bias (planted_bias.h) keeps an animated history's cached radiance
  RESTIR_HD GiBridge<Tracer> operator()(const SurfaceList& surfaces, int, bool temporal) const { return {this, surfaces, temporal, nullptr}; }
  RESTIR_HD GiBridge<Tracer, true> operator()(const SurfaceList& surfaces, int, bool temporal, RayCursor* cursor) const {
    return {this, surfaces, temporal, cursor};
  }
};

// One BSDF-sampled secondary hit and the radiance leaving it toward s (a path of `path` bounces,
// path.max_depth = the integrator's - 1). A delta lobe gets no sample: a plain path estimate goes
// to `specular` instead.
template <class Tracer>
RESTIR_HD GiReservoir gi_initial(const PathWorld& w, const Tracer& tracer, const PathOptions& path, GiTarget kind, const GSurface& s,
                                    Pcg32& rng, Rgb& specular) {
  GiReservoir r;
  r.confidence = 1;
  if (!s.valid) return r;
  BsdfSample bs;
  const float u_lobe = rng.next_float();
  const Vec2 u = rng.next_2d();
  const Frame shading = s.frame();
  const Vec3 wo_l = shading.to_local(s.wo);
  if (!bsdf_sample(s.bsdf, wo_l, u_lobe, u, bs) || !(bs.pdf > 0) || is_black(bs.f)) return r;
  const Vec3 wi = shading.to_world(bs.wi);
  const Ray ray = spawn_ray(s.p, s.ng, wi, w.ray_epsilon);
  if (bs.is_delta) {  // no NEE and no reconnection through a delta lobe: a plain path estimate
    specular = bs.f * std::fabs(bs.wi.z) / bs.pdf * path_radiance(w, tracer, path, ray, rng);
    return r;
  }
  GiSample x;
  x.suffix = rng;  // the stream path_radiance draws from, for replays in other frames
  x.radiance = path_radiance(w, tracer, path, ray, rng, /*skip_first_emission=*/true);
  Hit hit;
  float pdf = bs.pdf;
  if (tracer.intersect(ray, hit)) {
    const SurfaceInteraction si = surface_interaction(w.scene, ray, hit);
    x.position = si.p;
    x.normal = si.ng;
    x.geom = si.geom;
    x.prim = si.prim;
    // The sample is valued along the direction from the visible point to x_s (as every shift
    // sees it), so its density is taken there too: the traced ray left from an offset origin, and
    // near contact (x_s within a few epsilons) the two directions differ enough to bias f/p.
    const Vec3 wi_pos = normalize(si.p - s.p);
    pdf = bsdf_pdf(s.bsdf, wo_l, shading.to_local(wi_pos));
  } else {
    x.infinite = true;
    x.position = wi;
  }
  const float t = gi_target(w, tracer, kind, s, x, false);  // visible: it was traced
  if (pdf > 0) restir::stream(r, x, t, t / pdf, rng.next_float());
  restir::finalize(r);
  return r;
}

// Direct light at a non-delta visible point: one light sample (no MIS: the GI samples exclude
// emission, so light sampling is the only strategy for it).
template <class Tracer>
RESTIR_HD Rgb gi_direct(const PathWorld& w, const Tracer& tracer, const GSurface& s, Pcg32& rng) {
  if (!s.valid || bsdf_is_delta(s.bsdf)) return Rgb(0);
  LightSample ls;
  const float u_select = rng.next_float();
  const Vec2 u = rng.next_2d();
  if (!w.lights.sample(s.p, u_select, u, ls) || !(ls.pdf > 0)) return Rgb(0);
  const Frame shading = s.frame();
  const Vec3 wi_l = shading.to_local(ls.wi);
  const Rgb f = bsdf_eval(s.bsdf, shading.to_local(s.wo), wi_l) * std::fabs(wi_l.z);
  if (is_black(f)) return Rgb(0);
  return tracer.occluded(shadow_ray_to_light(s.p, s.ng, ls, w.ray_epsilon)) ? Rgb(0) : f * ls.radiance / ls.pdf;
}

// A pixel's radiance: emission seen, the specular and direct estimates, and f(x) W of its sample.
RESTIR_HD inline Rgb gi_shade(const GSurface& sf, const GiReservoir& r, Rgb specular) {
  Rgb L = sf.valid ? sf.le + specular : sf.le;
  if (sf.valid && r.has_sample()) L += gi_integrand(sf, r.sample) * r.ucw;  // visible: the target included it
  mark_non_finite(r, L);
  return L;
}

}  // namespace rl
