// Primary hits of a frame (the "G-buffer" of a real-time renderer): what every ReSTIR pass needs
// to evaluate target functions at a pixel, to reproject into the previous frame and to judge
// whether two pixels are similar enough to share samples.
#pragma once
#include <vector>

#include "integrators/integrator.h"
#include "scene/bsdf.h"

namespace rl {

struct GSurface {
  bool valid = false;   // the primary ray hit a surface
  Vec3 p;               // hit point
  Vec3 ng, ns;          // geometric and shading normals
  Frame frame;          // shading frame around ns
  Vec3 wo;              // world direction toward the camera
  float depth = 0;      // distance from the camera
  Bsdf bsdf;
  Rgb emitted{0};       // emission leaving the hit toward the camera
  Rgb background{0};    // environment radiance when the ray escaped (valid == false)
  // Where this point and its shading normal were one frame earlier: moved back with its object's
  // animation (the motion vector of an animated scene); p and ns for static geometry.
  Vec3 p_previous, ns_previous;
};

struct GBuffer {
  int width = 0, height = 0;
  std::vector<GSurface> pixels;
  const GSurface& at(int x, int y) const { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
};

// The G-buffer entry of a primary ray and its closest hit (null: it escaped). back[a] (optional,
// one per scene animation) maps a point of animation a's objects to where it was a frame earlier.
void fill_gsurface(const RenderContext& ctx, const Ray& ray, const Hit* hit, GSurface& s,
                   const std::vector<Mat4>* back = nullptr);
// Those maps for frame f (identity at frame 0): animation(f - 1) o animation(f)^-1.
std::vector<Mat4> motion_back(const Scene& scene, int frame);

// One primary ray per pixel for sample `sample` of frame `frame` (sample pattern + pixel filter).
void build_gbuffer(const RenderContext& ctx, const PerspectiveCamera& camera, int frame, int sample, GBuffer& g);

// Pixel of the previous frame that saw world point p; false when off screen or behind the camera.
bool reproject(const PerspectiveCamera& previous, Vec3 p, int& x, int& y);

// Bitterli et al. 2020 §4 / RTXDI: two surfaces may share samples when their depths differ by less
// than depth_threshold (relative) and their normals by less than normal_threshold_deg.
bool similar_surfaces(const GSurface& a, const GSurface& b, float depth_threshold, float normal_threshold_deg);

}  // namespace rl
