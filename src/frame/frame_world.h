// A frame's world as the per-pixel stages see it (ARCHITECTURE.md, "Backends"): this frame's
// scene, lights and ray tracer and -- in an animated scene -- the previous frame's, with the rigid
// motion of each animation between the two frames. Flat and trivially copyable, so that one
// definition of every stage runs on every backend: the CPU backend fills it with views of the
// host's scene and Embree (cpu_backend.h, no copy), the BVH backends with views of their copies
// in the execution policy's memory (bvh_backend.h: host memory, or the GPU's).
#pragma once
#include <cstdint>

#include "core/math.h"
#include "scene/lights_view.h"
#include "scene/scene_view.h"

namespace rl {

// What one bounce of a path reads: the scene, its lights, and the ray offset.
struct PathWorld {
  SceneView scene;
  LightsView lights;
  float ray_epsilon = 1e-4f;
};

// Tracer: the per-pixel stages' ray queries (EmbreeTracer on the CPU backend, BvhTracer on the
// others), anything with
//   bool occluded(const Ray&) const;            // any hit in [tmin, tmax]
//   bool intersect(const Ray&, Hit&) const;     // closest hit
template <class Tracer>
struct FrameWorld {
  PathWorld world;  // this frame's scene and lights
  Tracer tracer;    // ... and rays through them
  // The previous frame's scene, lights and rays (FrameInfo::previous_scene: an animated scene
  // whose integrator keeps it, Integrator::needs_previous_scene). Unset without has_previous.
  PathWorld previous_world;
  Tracer previous_tracer;
  bool has_previous = false;
  // The lights one frame earlier (FrameInfo::previous_lights: an animated scene whose lights move).
  LightsView previous_lights;
  bool has_previous_lights = false;
  // Per animation a: where a point of its objects was one frame earlier (back[a], motion_back) and
  // the inverse map (forward[a]); animation_count = 0 in a scene without animations.
  const Mat4* back = nullptr;
  const Mat4* forward = nullptr;
  uint32_t animation_count = 0;
  bool animated = false;  // scene_animated: something moves over the sequence
};

}  // namespace rl
