// Primary hits of a frame (the "G-buffer" of a real-time renderer): what every ReSTIR pass needs
// to evaluate target functions at a pixel, to reproject into the previous frame and to judge
// whether two pixels are similar enough to share samples.
#pragma once
#include <new>
#include <vector>

#include "core/unit_vector.h"
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

// What the G-buffer stores of a GSurface: 48 bytes instead of 160 (issue 48: compact state; as
// Falcor's and RTXDI's packed G-buffers). Exact: the point, its depth, the shading normal, the
// material and the reflectance its texture gave (GSurface::bsdf is make_bsdf of the two again, the
// same bits). The geometric normal in 16 bits a component of the octahedral map (core/unit_vector.h,
// < 4.3e-5 radians off: it offsets rays and decides sides, and pt.reconnection=footprint reads its
// cosine with the view direction -- a threshold both directions of a shift read from the same
// stored surface). The view direction is not stored: the camera is a pinhole, so it is the
// direction from the point to the camera's position (GBufferView::eye), -ray.d to float rounding. The emission toward the camera (GSurface::le) is
// the pixel's own -- no neighbour and no later frame reads it -- so it is kept beside the G-buffer
// for the current frame only (GBufferView::emitted).
inline constexpr uint32_t kNoGSurface = 0xffffffffu;  // GPacked::material where the ray escaped
struct GPacked {
  Vec3 p;
  float depth = 0;
  uint32_t material = kNoGSurface;
  Rgb reflectance{0};
  Vec3 ns;
  OctSnorm16 ng;
  RESTIR_HD bool valid() const { return material != kNoGSurface; }
};
static_assert(sizeof(GPacked) <= 48, "the compact G-buffer's budget (issue 48)");
RESTIR_HD inline Vec3 packed_shading_normal(const GPacked& g) { return g.ns; }
// The stored form of s, whose BSDF is make_bsdf(materials[material], reflectance).
RESTIR_HD inline GPacked pack_surface(const GSurface& s, uint32_t material, Rgb reflectance) {
  GPacked g;
  if (!s.valid) return g;
  g.p = s.p, g.depth = s.depth, g.material = material, g.reflectance = reflectance;
  g.ns = s.ns, g.ng = OctSnorm16::encode(s.ng);
  return g;
}
// The working form again, seen from the camera at `eye` (le: the pixel's emission toward the
// camera, 0 where not kept).
RESTIR_HD inline GSurface unpack_surface(const GPacked& g, const MaterialParams* materials, Vec3 eye, Rgb le = Rgb(0)) {
  if (!g.valid()) {
    GSurface s;
    s.le = le;
    return s;
  }
  // Each member once (a default-initialized GSurface assigned field by field wrote it twice).
  return GSurface{true, g.p, g.ng.decode(), g.ns, normalize(eye - g.p), g.depth, make_bsdf(materials[g.material], g.reflectance), le};
}

// Where a G-buffer point and its shading normal were one frame earlier: moved back with its
// object's animation (the motion vector of an animated scene); p and ns for static geometry. Kept
// beside the surfaces, not in them: only temporal reuse and SSR's history read it, and the 24 bytes
// made every GSurface that the spatial pass fetches from a neighbour larger (issue 9: 148 -> 124
// bytes; padding it by 64 bytes had cost DI's spatial pass 4-10%).
struct GMotion {
  Vec3 p_previous, ns_previous;
};
// Pixel i's motion: motion[i], or where there is no motion array (a static scene) the point's own.
RESTIR_HD inline GMotion motion_of(const GPacked* pixels, const GMotion* motion, size_t i) {
  return motion ? motion[i] : GMotion{pixels[i].p, packed_shading_normal(pixels[i])};
}

// The G-buffer entry of a primary ray and its closest hit (null: it escaped), over the
// device-shaped views (the CUDA backend's too), into g and the emission toward the camera into le.
// back[a] (back_count of them, one per scene animation; may be null) maps a point of animation a's
// objects to where it was a frame earlier; the point's motion goes to *motion where that is not null.
RESTIR_HD inline void fill_gpacked(const SceneView& scene, const LightsView& lights, const Ray& ray, const Hit* hit, GPacked& g, Rgb& le,
                                   const Mat4* back, uint32_t back_count, GMotion* motion = nullptr) {
  g = GPacked{};
  if (motion) *motion = GMotion{};
  if (!hit) {
    le = lights.environment_radiance(ray.d);
    return;
  }
  const SurfaceInteraction si = surface_interaction(scene, ray, *hit);
  GSurface s;
  s.valid = true;
  s.p = si.p;
  s.ng = si.ng;
  s.ns = si.ns;
  s.wo = -ray.d;
  s.depth = hit->t;
  const MaterialParams& mat = scene.materials[si.material];
  g = pack_surface(s, si.material, material_reflectance(scene, mat, si.uv));
  const uint32_t e = lights.emitter_at(si);
  le = e != kNoEmitter ? lights.emitted(e, si.ng, s.wo) : Rgb(0);
  if (!motion) return;
  motion->p_previous = s.p;
  motion->ns_previous = s.ns;
  const int a = si.is_sphere ? scene.spheres[si.prim].animation : scene.meshes[si.geom].animation;
  if (back && a >= 0 && uint32_t(a) < back_count) {
    motion->p_previous = back[a].apply_point(s.p);
    motion->ns_previous = normalize(back[a].apply_vector(s.ns));  // rigid: the rotation part
  }
}
// The same as a working surface (what a stage reading the G-buffer entry back gets).
RESTIR_HD inline void fill_gsurface(const SceneView& scene, const LightsView& lights, const Ray& ray, const Hit* hit, GSurface& s,
                                    const Mat4* back, uint32_t back_count, GMotion* motion = nullptr) {
  GPacked g;
  Rgb le;
  fill_gpacked(scene, lights, ray, hit, g, le, back, back_count, motion);
  s = unpack_surface(g, scene.materials, ray.o, le);
}

// A frame's G-buffer on the host (tests, tools): w x h packed surfaces, the emission toward the
// camera, and a motion array where the scene has animations.
struct GBuffer {
  int width = 0, height = 0;
  std::vector<GPacked> pixels;
  std::vector<Rgb> emitted;
  // One per pixel in an animated scene (build_gbuffer fills it); empty in a static one, where
  // each point's previous position is its own (motion_at).
  std::vector<GMotion> motion;
  // A copy of the scene's materials, which GSurface::bsdf is made from: a host G-buffer may outlive
  // the acceleration structure whose scene view it was built from (the frames' views point into
  // their backend's own copy instead).
  std::vector<MaterialParams> materials;
  Vec3 eye;  // the camera's position
  // Sized for w x h pixels, with a motion array when `animated` (no clearing: fill_gpacked writes
  // every entry).
  void resize(int w, int h, bool animated) {
    width = w, height = h;
    pixels.resize(size_t(w) * size_t(h));
    emitted.resize(pixels.size());
    if (animated)
      motion.resize(pixels.size());
    else
      motion.clear();
  }
  size_t index(int x, int y) const { return size_t(y) * size_t(width) + size_t(x); }
  GSurface at(int x, int y) const { return unpack_surface(pixels[index(x, y)], materials.data(), eye, emitted[index(x, y)]); }
  // The motion array, null without one (motion_of's convention); where fill_gpacked writes pixel i's.
  const GMotion* motion_data() const { return motion.empty() ? nullptr : motion.data(); }
  GMotion* motion_slot(size_t i) { return motion.empty() ? nullptr : &motion[i]; }
  GMotion motion_at(int x, int y) const { return motion_of(pixels.data(), motion_data(), index(x, y)); }
};

// The surfaces of one resampling (0 = the canonical domain), as the integrators' bridges (mis.h)
// read them: the canonical one unpacked once by the pass, another where it is read, into a cache
// of one surface -- a pass keeps no array of unpacked neighbours (a GPU thread's state stays the
// packed pointers and one surface), and a bridge that reads one domain several times in a row
// unpacks it once.
static_assert(std::is_trivially_destructible_v<GSurface>);
struct SurfaceList {
  SurfaceList() = default;
  RESTIR_HD SurfaceList(const GSurface* canonical_, const GPacked* const* packed_, const MaterialParams* materials_, Vec3 eye_)
      : canonical(canonical_), packed(packed_), materials(materials_), eye(eye_) {}
  const GSurface* canonical = nullptr;
  const GPacked* const* packed = nullptr;  // packed[i] for i >= 1
  const MaterialParams* materials = nullptr;
  Vec3 eye;  // the camera that saw packed[i], i >= 1
  // Domain i's surface. Another domain's is valid until a read of a third one overwrites the cache:
  // read one domain at a time (every bridge passes it straight to the function that uses it).
  RESTIR_HD const GSurface& operator[](int i) const {
    if (i == 0) return *canonical;
    if (i != cached) {
      // Made in place (GSurface is trivially destructible): an assignment built the 160-byte
      // surface on the stack and copied it, and the copy's wide loads of the narrow stores just
      // made stalled -- over half of target_from's time in ReSTIR PT's spatial pass (perf).
      new (&cache.s) GSurface(unpack_surface(*packed[i], materials, eye));
      cached = i;
    }
    return cache.s;
  }
  RESTIR_HD Vec3 point(int i) const { return i == 0 ? canonical->p : packed[i]->p; }
  // packed[cached] unpacked; left unwritten until then (a bridge is made per pixel and resampling,
  // and most read no neighbour twice: default-initializing 160 bytes each time showed in perf).
  union Cache {
    GSurface s;
    RESTIR_HD Cache() {}
  };
  mutable Cache cache;
  mutable int cached = -1;
};

// Those maps for frame f (identity at frame 0): animation(f - 1) o animation(f)^-1.
std::vector<Mat4> motion_back(const Scene& scene, int frame);

// One primary ray per pixel for sample `sample` of frame `frame` (sample pattern + pixel filter),
// traced on the CPU backend (Embree): every pixel's surface into pixels[] and its emission toward
// the camera into emitted[] (camera.width() x camera.height()), and its motion into motion[] unless
// that is null. back: motion_back's maps (back_count of them). The CPU backend's primary-hit stage
// (cpu_backend.h).
void build_gbuffer(const RenderContext& ctx, const PerspectiveCamera& camera, int frame, int sample, const Mat4* back,
                   uint32_t back_count, GPacked* pixels, Rgb* emitted, GMotion* motion);
// The same into g, sized for the camera, with a motion array where the scene has animations
// (tests and tools that keep a host GBuffer).
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
// than depth_threshold (relative to the first's) and their normals by less than normal_threshold_deg.
// Here for two valid surfaces by their depths and shading normals; below for the surfaces themselves.
RESTIR_HD inline bool similar_surfaces(float depth_a, Vec3 ns_a, float depth_b, Vec3 ns_b, float depth_threshold,
                                       float normal_threshold_deg) {
  if (std::fabs(depth_a - depth_b) > depth_threshold * std::max(depth_a, 1e-6f)) return false;
  return dot(ns_a, ns_b) >= std::cos(normal_threshold_deg * kPi / 180.0f);
}
RESTIR_HD inline bool similar_surfaces(const GSurface& a, const GSurface& b, float depth_threshold, float normal_threshold_deg) {
  return a.valid && b.valid && similar_surfaces(a.depth, a.ns, b.depth, b.ns, depth_threshold, normal_threshold_deg);
}
// A surface of depth `depth` and shading normal `ns` (valid) against a stored one.
RESTIR_HD inline bool similar_surfaces(float depth, Vec3 ns, const GPacked& b, float depth_threshold, float normal_threshold_deg) {
  return b.valid() && similar_surfaces(depth, ns, b.depth, packed_shading_normal(b), depth_threshold, normal_threshold_deg);
}
RESTIR_HD inline bool similar_surfaces(const GSurface& a, const GPacked& b, float depth_threshold, float normal_threshold_deg) {
  return a.valid && similar_surfaces(a.depth, a.ns, b, depth_threshold, normal_threshold_deg);
}

}  // namespace rl
