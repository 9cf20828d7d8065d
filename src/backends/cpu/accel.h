// Embree 3 ray queries over a Scene: triangle meshes (one Embree geometry each) and all spheres
// (one RTC_GEOMETRY_TYPE_SPHERE_POINT geometry). The only place that talks to Embree.
#pragma once
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "core/math.h"
#include "scene/ray_queries.h"
#include "scene/scene.h"
#include "scene/scene_view.h"

namespace rl {

// Every ray a frame traced, for the benchmarks that replay them through Embree alone: how much of
// a frame the rays themselves take, and what is left for the renderer's own work (issue 9).
// Filled from many threads; the order of the rays is not deterministic, the set is.
class RayLog {
 public:
  RayLog();
  ~RayLog();
  RayLog(const RayLog&) = delete;
  RayLog& operator=(const RayLog&) = delete;
  void add(const Ray& ray, bool any_hit);
  // The rays logged so far: closest-hit queries, any-hit (shadow) queries.
  std::vector<Ray> closest() const;
  std::vector<Ray> any_hit() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The CPU backend's RayQueries (Embree), and the scalar queries and hit-point shading that the
// per-pixel integrators use.
class Accel final : public RayQueries {
 public:
  explicit Accel(const Scene& scene);
  ~Accel();
  Accel(const Accel&) = delete;
  Accel& operator=(const Accel&) = delete;

  // After animate_scene() moved the scene this Accel was built from (same meshes and spheres):
  // re-reads the animated ones, refits their BVHs and rebuilds the top level. Not thread-safe.
  void update() override;

  // Closest hit in (ray.tmin, ray.tmax). Thread-safe.
  bool intersect(const Ray& ray, Hit& hit) const;
  // Any hit in (ray.tmin, ray.tmax). Thread-safe.
  bool occluded(const Ray& ray) const;
  // Batched queries, the wavefront core's ray interface: hits[i] / blocked[i] answer rays[i]
  // (same results as the scalar calls). Embree's stream API (rtcIntersect1M / rtcOccluded1M), which
  // traverses `coherent` batches (camera rays) as packets. Thread-safe; call from many threads on
  // disjoint spans.
  void intersect(std::span<const Ray> rays, std::span<Hit> hits, bool coherent = false) const;
  void occluded(std::span<const Ray> rays, std::span<uint8_t> blocked, bool coherent = false) const;
  // RayQueries: the span queries above over parallel chunks of the batch.
  void intersect_batch(std::span<const Ray> rays, std::span<Hit> hits, bool coherent = false) const override;
  void occluded_batch(std::span<const Ray> rays, std::span<uint8_t> blocked) const override;
  const char* backend_name() const override { return "cpu"; }
  SurfaceInteraction interaction(const Ray& ray, const Hit& hit) const { return surface_interaction(view_, ray, hit); }
  // The scene as per-sample code sees it (scene_view.h), of the pose update() last read.
  const SceneView& scene_view() const { return view_; }
  // Bumped by every update() that moved the scene: a backend holding a copy of the scene (the
  // CUDA path tracer) copies it again when this differs from the generation it copied.
  uint64_t generation() const { return generation_; }
  uint32_t sphere_geom() const { return uint32_t(scene_.meshes.size()); }
  const Scene& scene() const { return scene_; }
  // Scene-size dependent epsilon used to offset spawned rays off surfaces.
  float ray_epsilon() const { return epsilon_; }
  // While set (benchmarks; null = off), every query, scalar or batched, also appends its ray to `log`.
  void set_ray_log(RayLog* log) { log_ = log; }

 private:
  struct Impl;
  const Scene& scene_;
  std::unique_ptr<Impl> impl_;
  SceneViewData view_data_;
  SceneView view_;
  float epsilon_ = 1e-4f;
  bool animated_ = false;  // the scene has animated shapes: update() has work
  uint64_t generation_ = 0;  // counts the update()s that moved something
  RayLog* log_ = nullptr;
};

}  // namespace rl
