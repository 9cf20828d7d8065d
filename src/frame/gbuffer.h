// Primary hits of a frame (the "G-buffer" of a real-time renderer): what every ReSTIR pass needs
// to evaluate target functions at a pixel, to reproject into the previous frame and to judge
// whether two pixels are similar enough to share samples.
#pragma once
#include <vector>

#include "frame/integrator.h"
#include "scene/bsdf.h"
#include "scene/lights_view.h"
#include "scene/scene_view.h"

namespace rl {

struct GSurface {
  bool valid = false;   // the primary ray hit a surface
  Vec3 p;               // hit point
  Vec3 ng, ns;          // geometric and shading normals
  Vec3 wo;              // world direction toward the camera
  float depth = 0;      // distance from the camera
  Bsdf bsdf;
  // Radiance reaching the camera along the primary ray from what it met first: the emission of
  // the hit surface toward the camera (valid), or the environment's (the ray escaped).
  Rgb le{0};

  // The shading frame around ns. Rebuilt where it is used rather than stored: the same bits as
  // Frame::from_normal(ns) at the hit, and 36 bytes less per pixel in every pass that reads
  // neighbours' surfaces (issue 9: compact ReSTIR state).
  RESTIR_HD Frame frame() const { return Frame::from_normal(ns); }
};

// Where a G-buffer point and its shading normal were one frame earlier: moved back with its
// object's animation (the motion vector of an animated scene); p and ns for static geometry. Kept
// beside the surfaces, not in them: only temporal reuse and SSR's history read it, and the 24 bytes
// made every GSurface that the spatial pass fetches from a neighbour larger (issue 9: 148 -> 124
// bytes; padding it by 64 bytes had cost DI's spatial pass 4-10%).
struct GMotion {
  Vec3 p_previous, ns_previous;
};
// Pixel i's motion: motion[i], or where there is no motion array (a static scene) the point's own.
RESTIR_HD inline GMotion motion_of(const GSurface* pixels, const GMotion* motion, size_t i) {
  return motion ? motion[i] : GMotion{pixels[i].p, pixels[i].ns};
}

struct GBuffer {
  int width = 0, height = 0;
  std::vector<GSurface> pixels;
  // One per pixel in an animated scene (build_gbuffer fills it); empty in a static one, where
  // each point's previous position is its own (motion_at).
  std::vector<GMotion> motion;
  // Sized for w x h pixels, with a motion array when `animated` (no clearing: fill_gsurface writes
  // every entry).
  void resize(int w, int h, bool animated) {
    width = w, height = h;
    pixels.resize(size_t(w) * size_t(h));
    if (animated)
      motion.resize(pixels.size());
    else
      motion.clear();
  }
  const GSurface& at(int x, int y) const { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
  // The motion array, null without one (motion_of's convention); where fill_gsurface writes pixel i's.
  const GMotion* motion_data() const { return motion.empty() ? nullptr : motion.data(); }
  GMotion* motion_slot(size_t i) { return motion.empty() ? nullptr : &motion[i]; }
  GMotion motion_at(int x, int y) const { return motion_of(pixels.data(), motion_data(), size_t(y) * size_t(width) + size_t(x)); }
};

// The G-buffer entry of a primary ray and its closest hit (null: it escaped), over the
// device-shaped views (the CUDA backend's too). back[a] (back_count of them, one per scene
// animation; may be null) maps a point of animation a's objects to where it was a frame earlier;
// the point's motion goes to *motion where that is not null.
RESTIR_HD inline void fill_gsurface(const SceneView& scene, const LightsView& lights, const Ray& ray, const Hit* hit, GSurface& s,
                                    const Mat4* back, uint32_t back_count, GMotion* motion = nullptr) {
  s = GSurface{};
  if (motion) *motion = GMotion{};
  if (!hit) {
    s.le = lights.environment_radiance(ray.d);
    return;
  }
  const SurfaceInteraction si = surface_interaction(scene, ray, *hit);
  s.valid = true;
  s.p = si.p;
  s.ng = si.ng;
  s.ns = si.ns;
  s.wo = -ray.d;
  s.depth = hit->t;
  const MaterialParams& mat = scene.materials[si.material];
  s.bsdf = make_bsdf(mat, material_reflectance(scene, mat, si.uv));
  const uint32_t e = lights.emitter_at(si);
  if (e != kNoEmitter) s.le = lights.emitted(e, si.ng, s.wo);
  if (!motion) return;
  motion->p_previous = s.p;
  motion->ns_previous = s.ns;
  const int a = si.is_sphere ? scene.spheres[si.prim].animation : scene.meshes[si.geom].animation;
  if (back && a >= 0 && uint32_t(a) < back_count) {
    motion->p_previous = back[a].apply_point(s.p);
    motion->ns_previous = normalize(back[a].apply_vector(s.ns));  // rigid: the rotation part
  }
}
// Those maps for frame f (identity at frame 0): animation(f - 1) o animation(f)^-1.
std::vector<Mat4> motion_back(const Scene& scene, int frame);

// One primary ray per pixel for sample `sample` of frame `frame` (sample pattern + pixel filter),
// traced on the CPU backend (Embree): every pixel's surface into pixels[] (camera.width() x
// camera.height()), and its motion into motion[] unless that is null. back: motion_back's maps
// (back_count of them). The CPU backend's primary-hit stage (cpu_backend.h).
void build_gbuffer(const RenderContext& ctx, const PerspectiveCamera& camera, int frame, int sample, const Mat4* back,
                   uint32_t back_count, GSurface* pixels, GMotion* motion);
// The same into g, sized for the camera, with a motion array where the scene has animations
// (integrators that keep a host GBuffer: ssr).
void build_gbuffer(const RenderContext& ctx, const PerspectiveCamera& camera, int frame, int sample, GBuffer& g);

// Pixel of the previous frame that saw world point p; false when off screen or behind the camera.
RESTIR_HD inline bool reproject(const PerspectiveCamera& previous, Vec3 p, int& x, int& y) {
  Vec2 r;
  if (!previous.project(p, r)) return false;
  x = int(r.x);
  y = int(r.y);
  return x >= 0 && y >= 0 && x < previous.width() && y < previous.height();
}

// Bitterli et al. 2020 §4 / RTXDI: two surfaces may share samples when their depths differ by less
// than depth_threshold (relative) and their normals by less than normal_threshold_deg.
RESTIR_HD inline bool similar_surfaces(const GSurface& a, const GSurface& b, float depth_threshold, float normal_threshold_deg) {
  if (!a.valid || !b.valid) return false;
  if (std::fabs(a.depth - b.depth) > depth_threshold * std::max(a.depth, 1e-6f)) return false;
  return dot(a.ns, b.ns) >= std::cos(normal_threshold_deg * kPi / 180.0f);
}

}  // namespace rl
