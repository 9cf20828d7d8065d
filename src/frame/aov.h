// Arbitrary output variables (AOVs) of a frame: what a denoiser (src/post/) and a user's own tools
// need beside the radiance, one array per quantity, row-major (row 0 at the top), width x height.
// Filled by the renderer's own primary-ray pass through each pixel's centre (build_aovs) for every
// integrator alike, so they do not depend on the integrator, its sample pattern or its seed --
// except `emission`, which is what the frame's own camera samples saw.
// A plain, stable API (the Python bindings read it as it is): fields are added, never renamed.
// docs/denoise.md lists the EXR channels `restir render --aov-dir` writes from it.
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/math.h"

namespace rl {

struct RenderContext;
class PerspectiveCamera;

// surface_id of a pixel whose primary ray escaped (no surface).
inline constexpr uint32_t kNoSurface = 0xffffffffu;

struct Aovs {
  int width = 0, height = 0;
  // The BSDF's reflectance at the primary hit (aov_albedo): diffuse and coated-diffuse base albedo,
  // a conductor's normal-incidence Fresnel colour, 1 for a dielectric. 0 where no surface.
  std::vector<Rgb> albedo;
  // The shading normal at the primary hit, world space, unit, turned to the camera's side
  // (dot(normal, toward camera) >= 0). 0 where no surface.
  std::vector<Vec3> normal;
  // Linear view depth: camera-space z of the hit (distance along the camera's forward axis; pbrt's
  // "Pz", Falcor's linear Z), in world units. 0 where no surface.
  std::vector<float> depth;
  // Its screen-space derivative, max(|dz/dx|, |dz/dy|) in world units per pixel (Falcor's SVGF
  // "fwidth" of linear Z), from one-sided differences to the neighbours on the same kind of
  // surface (escaped neighbours are skipped). 0 where no surface.
  std::vector<float> depth_gradient;
  // Motion vector: where the hit point was in the previous frame's raster minus where it is now, in
  // pixels (x right, y down); add it to a pixel's centre to find its history. Uses the previous
  // camera and, in an animated scene, the point's object motion (GMotion). 0 on the first frame,
  // where no surface, and where the point was behind the previous camera.
  std::vector<Vec2> motion;
  // Radiance emitted toward the camera as the frame's primary rays saw it: the mean over the
  // integrator's own camera samples (camera_ray: sample pattern, pixel filter, seed, render.spp) of
  // the hit surface's emission (GSurface::le), or the environment's radiance where a ray escaped.
  // Every integrator adds exactly this at its primary hits, so the frame minus it is reflected
  // light only: what a denoiser demodulates (at an emitter's edge the pixel centre's emission is not).
  std::vector<Rgb> emission;
  // Which shape the primary ray hit: the mesh index, or (spheres) the mesh count + sphere index;
  // kNoSurface where it escaped. A mesh is one id (primitive ids would break at every triangle).
  std::vector<uint32_t> surface_id;

  size_t index(int x, int y) const { return size_t(y) * size_t(width) + size_t(x); }
  bool valid(size_t i) const { return surface_id[i] != kNoSurface; }
  void resize(int w, int h);
};

// The primary-ray pass: one ray through each pixel's centre of `camera`, traced on the CPU backend,
// filled through fill_gsurface (gbuffer.h: the integrators' own G-buffer code). `previous` is the
// previous frame's camera (null on the first frame); `frame` the frame index (object motion).
void build_aovs(const RenderContext& ctx, const PerspectiveCamera& camera, const PerspectiveCamera* previous,
                int frame, Aovs& out);

// The AOVs as EXR channels (name, planar floats), in the order `--aov-dir` writes them: Albedo.R/G/B,
// N.X/Y/Z, Z, dZ, Motion.X/Y, Emission.R/G/B, SurfaceId (as float: exact below 2^24). One
// multi-channel EXR per frame, like pbrt-v4's "gbuffer" film and Mitsuba's aov integrator.
std::vector<std::pair<std::string, std::vector<float>>> aov_channels(const Aovs& a);

}  // namespace rl
