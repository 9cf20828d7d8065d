// The wavefront core's ray interface (ARCHITECTURE.md, "Backends"): closest-hit and any-hit
// queries over a whole batch of rays. The CPU backend answers them with Embree (Accel), the CUDA
// backend with its own BVH traversed on the GPU (src/backends); integrators that issue their rays
// in batches (the wavefront path tracer) see only this interface.
#pragma once
#include <cmath>
#include <cstdint>
#include <span>

#include "core/math.h"

namespace rl {

inline constexpr uint32_t kInvalidId = 0xffffffffu;

struct Hit {
  float t = kInfinity;
  uint32_t geom = kInvalidId;  // mesh index, or the sphere geometry (= number of meshes) for spheres
  uint32_t prim = kInvalidId;  // triangle index in the mesh, or sphere index
  float u = 0, v = 0;          // barycentrics of vertices 1 and 2 (triangles)
  RESTIR_HD bool valid() const { return geom != kInvalidId; }
};

// The rays every backend answers: a finite origin within 1e18 and direction, 0 <= tmin <= tmax.
// Anything else (a NaN from a degenerate sample) hits nothing, on every backend alike. (Embree
// asserts on such rays -- RTCRay::valid -- so Accel must not pass them on.)
RESTIR_HD inline bool ray_queryable(const Ray& r) {
  constexpr float kLarge = 1e18f;
  return is_finite(r.o) && is_finite(r.d) && std::fabs(r.o.x) < kLarge && std::fabs(r.o.y) < kLarge &&
         std::fabs(r.o.z) < kLarge && std::isfinite(r.tmin) && r.tmin >= 0 && !std::isnan(r.tmax) && r.tmax >= r.tmin;
}

// Ray leaving p (with geometric normal ng) in direction d, offset to the side d points to, so it
// does not re-hit the surface it starts on.
RESTIR_ALWAYS_INLINE RESTIR_HD inline Ray spawn_ray(Vec3 p, Vec3 ng, Vec3 d, float eps) {
  Vec3 off = ng * (dot(d, ng) >= 0 ? eps : -eps);
  return Ray{p + off, d, 0.0f, kInfinity};
}
// Shadow ray from p to the point q (with normal nq, zero for points/env), offsetting both ends.
RESTIR_ALWAYS_INLINE RESTIR_HD inline Ray spawn_ray_to(Vec3 p, Vec3 ng, Vec3 q, Vec3 nq, float eps) {
  Vec3 d0 = q - p;
  Vec3 o = p + ng * (dot(d0, ng) >= 0 ? eps : -eps);
  Vec3 target = q + nq * (dot(o - q, nq) >= 0 ? eps : -eps);
  Vec3 d = target - o;
  float len = length(d);
  return Ray{o, d / len, 0.0f, len * (1 - 1e-4f)};
}

class RayQueries {
 public:
  virtual ~RayQueries() = default;
  // hits[i] / blocked[i] answer rays[i] (closest hit / any hit in [tmin, tmax]). One call carries a
  // whole batch from one thread; the backend spreads it over its threads or its device. `coherent`:
  // the rays start near each other and point alike (camera rays), a hint.
  virtual void intersect_batch(std::span<const Ray> rays, std::span<Hit> hits, bool coherent = false) const = 0;
  virtual void occluded_batch(std::span<const Ray> rays, std::span<uint8_t> blocked) const = 0;
  // After animate_scene() moved the scene the queries were built from: follow it. Not thread-safe.
  virtual void update() = 0;
  virtual const char* backend_name() const = 0;
};

}  // namespace rl
