// Compile-time check (CUDA builds only): one kernel, never launched, that calls every per-sample
// function meant to run on the GPU -- the ones the CUDA path tracer uses and the ones the ReSTIR
// integrators will need there (G-buffer, light sampling in every form, reprojection, similarity).
// nvcc compiles each for the device here, and --Werror cross-execution-space-call turns any host-only
// call inside them into a build error in CI, long before a GPU is at hand.
#include "backends/cuda/cuda_exec.cuh"

#include "backends/bvh_traverse.h"
#include "integrators/restir_di/di_candidates.h"
#include "integrators/restir_di/di_kernel.h"
#include "frame/gbuffer.h"
#include "integrators/path/path_pixel.h"

namespace rl {

__global__ void device_compile_check(PathWorld w, BvhView bvh, PerspectiveCamera camera, CameraSampling cs, PathOptions opt,
                                     const Mat4* back, float* out) {
  const Ray ray = camera_ray(cs, camera, 1, 2, 3, 4);
  Hit hit;
  const bool found = bvh_trace(bvh, ray, false, &hit);
  GSurface g, h;
  fill_gsurface(w.scene, w.lights, ray, found ? &hit : nullptr, g, back, 2);
  fill_gsurface(w.scene, w.lights, ray, nullptr, h, nullptr, 0);
  int x = 0, y = 0;
  float acc = float(reproject(camera, g.p, x, y)) + float(similar_surfaces(g, h, 0.1f, 25.0f));
  const LightsView& L = w.lights;
  LightSample ls;
  acc += float(L.sample(g.p, 0.3f, Vec2(0.2f, 0.7f), ls)) + L.pdf(ls.emitter, g.p, ls.position, ls.normal);
  float pmf = 0;
  const uint32_t e = L.select_emitter(0.5f, &pmf);
  acc += float(L.sample_emitter(e, g.p, Vec2(0.1f, 0.9f), ls)) + L.selection_pmf(e) + L.power(e) + luminance(L.point_intensity(e));
  EmitterPoint ep;
  acc += float(L.sample_point(0.4f, Vec2(0.5f, 0.5f), ep)) + L.point_pdf(ep.emitter, ep.position);
  acc += luminance(L.emitted(e, g.ng, g.wo)) + L.environment_pdf(ray.d) + luminance(L.environment_radiance(ray.d));
  acc += float(L.triangle_emitter(0, 0) + L.sphere_emitter(0) + L.environment_emitter()) + float(L.has_environment());
  acc += float(L.is_delta(e)) + float(L.at_infinity(e)) + luminance(L.delta_emission(e, ls.wi)) + spot_falloff(0.9f, 0.8f, 0.95f);
  BsdfSample bs;
  acc += float(bsdf_sample(g.bsdf, Vec3(0, 0, 1), 0.5f, Vec2(0.3f, 0.3f), bs)) + bsdf_pdf(g.bsdf, Vec3(0, 0, 1), bs.wi) +
         luminance(bsdf_eval(g.bsdf, Vec3(0, 0, 1), bs.wi)) + bsdf_roughness(g.bsdf);
  // ReSTIR DI's integrand, shadow ray and light density at the G-buffer surface.
  const LightPoint lp{ls.position, ls.emitter};
  Ray shadow;
  acc += luminance(di_unshadowed(L, g, lp, w.ray_epsilon, &shadow)) + shadow.tmax;
  di_detail::LightView v;
  if (di_detail::view_light(L, g, lp, v)) acc += di_detail::light_density(L, g, lp, v) + di_detail::di_shadow_ray(L, g, lp, v, 1e-4f).tmax;
  // ReSTIR DI's batched light candidates (one thread runs its pixel's batch on the GPU).
  DiCandidateBatch batch;
  batch.n = 2;
  batch.emitter[0] = batch.emitter[1] = e;
  batch.pmf[0] = batch.pmf[1] = pmf;
  batch.ux[0] = batch.uy[1] = 0.25f, batch.uy[0] = batch.ux[1] = 0.75f;
  acc += float(di_eval_light_candidates(L, g, g.frame().to_local(g.wo), true, batch)) + batch.target[0] + batch.light_pdf[1];
  PathState st;
  st.ray = ray;
  PendingShadow sh;
  acc += float(path_bounce(w, opt, st, found ? &hit : nullptr, sh)) + float(bvh_trace(bvh, sh.ray, true, nullptr));
  *out = acc;
}

}  // namespace rl
