// Closest-hit and any-hit traversal of a Bvh (bvh.h), the same code on the host (tests, against
// Embree) and on the GPU (src/backends/cuda). Hits agree with Accel's: same t range (tmin <= t <=
// tmax, inclusive as Embree), same ids, same barycentrics (u, v of vertices 1 and 2), the same
// guard on rays Embree refuses (ray_queryable).
#pragma once
#include "backends/bvh.h"
#include "core/ray_counter.h"
#include "scene/ray_queries.h"

namespace rl {

// Ray-box slab test against [tmin, tmax]; inv_d = 1 / d with zeros replaced by a huge value of the
// same sign, so that an axis-parallel ray is tested against the slab it lies in, never NaN.
RESTIR_HD inline bool bvh_box_hit(Vec3 lo, Vec3 hi, Vec3 o, Vec3 inv_d, float tmin, float tmax, float& t_enter) {
  float tx0 = (lo.x - o.x) * inv_d.x, tx1 = (hi.x - o.x) * inv_d.x;
  float ty0 = (lo.y - o.y) * inv_d.y, ty1 = (hi.y - o.y) * inv_d.y;
  float tz0 = (lo.z - o.z) * inv_d.z, tz1 = (hi.z - o.z) * inv_d.z;
  float t0 = fmaxf(fmaxf(fminf(tx0, tx1), fminf(ty0, ty1)), fmaxf(fminf(tz0, tz1), tmin));
  float t1 = fminf(fminf(fmaxf(tx0, tx1), fmaxf(ty0, ty1)), fminf(fmaxf(tz0, tz1), tmax));
  // Robust BVH traversal (Ize 2013): widen the exit by 2 ulp-ish so that rounding in the slab
  // distances cannot make a ray that grazes a box's face miss a primitive lying on that face.
  t_enter = t0;
  return t0 <= t1 * 1.00000024f;
}

// Möller & Trumbore 1997; u, v weight vertices 1 and 2 (Embree's convention).
RESTIR_HD inline bool bvh_triangle_hit(const BvhPrimitive& p, const Ray& r, float tmin, float tmax, float& t, float& u, float& v) {
  const Vec3 e1 = p.b - p.a, e2 = p.c - p.a;
  const Vec3 pv = cross(r.d, e2);
  const float det = dot(e1, pv);
  if (det == 0 || !(std::fabs(det) > 0)) return false;
  const float inv = 1.0f / det;
  const Vec3 tv = r.o - p.a;
  const float uu = dot(tv, pv) * inv;
  if (uu < 0 || uu > 1) return false;
  const Vec3 qv = cross(tv, e1);
  const float vv = dot(r.d, qv) * inv;
  if (vv < 0 || uu + vv > 1) return false;
  const float tt = dot(e2, qv) * inv;
  if (!(tt >= tmin && tt <= tmax)) return false;
  t = tt, u = uu, v = vv;
  return true;
}

// Ray-sphere with the numerically robust discriminant of Haines et al. 2019 ("Precision
// Improvements for Ray/Sphere Intersection", Ray Tracing Gems ch. 7): the nearer root in range,
// else the farther (a ray starting inside hits the far side), as Embree's sphere geometry.
RESTIR_HD inline bool bvh_sphere_hit(const BvhPrimitive& p, const Ray& r, float tmin, float tmax, float& t) {
  const float radius = p.b.x;
  const Vec3 f = r.o - p.a;
  const float a = dot(r.d, r.d);
  const float b = -dot(f, r.d);  // half of the usual b, negated
  const Vec3 l = f + r.d * (b / a);
  const float disc = a * (radius * radius - dot(l, l));
  if (!(disc >= 0) || !(a > 0)) return false;
  const float c = dot(f, f) - radius * radius;
  const float q = b + std::copysign(std::sqrt(disc), b);
  float t0 = q != 0 ? c / q : 0.0f, t1 = q / a;
  if (t0 > t1) {
    const float s = t0;
    t0 = t1, t1 = s;
  }
  if (t0 >= tmin && t0 <= tmax) return t = t0, true;
  if (t1 >= tmin && t1 <= tmax) return t = t1, true;
  return false;
}

// Closest hit (any_hit = false) or any hit (true: returns at the first). hit is written only on
// a closest hit. Iterative, with a stack of the far children (kBvhMaxDepth deep).
RESTIR_HD inline bool bvh_trace(const BvhView& bvh, const Ray& ray, bool any_hit, Hit* hit) {
  if (bvh.node_count == 0 || !ray_queryable(ray)) return false;
  auto safe_inv = [](float d) { return std::fabs(d) > 1e-30f ? 1.0f / d : std::copysign(1e30f, d); };
  const Vec3 inv_d{safe_inv(ray.d.x), safe_inv(ray.d.y), safe_inv(ray.d.z)};
  const float tmin = ray.tmin;
  float tmax = ray.tmax;
  bool found = false;
  uint32_t stack[kBvhMaxDepth + 2];   // the farther children not yet visited ...
  float stack_t[kBvhMaxDepth + 2];    // ... and where the ray enters their boxes
  int sp = 0;
  uint32_t node = 0;
  for (;;) {
    const BvhNode& n = bvh.nodes[node];
    uint32_t next[2];
    float enter[2];
    int inner = 0;
    for (int c = 0; c < 2; ++c) {
      float te;
      if (n.child[c] == kBvhNone || !bvh_box_hit(n.lo[c], n.hi[c], ray.o, inv_d, tmin, tmax, te)) continue;
      if (n.count[c] == 0) {
        next[inner] = n.child[c], enter[inner] = te, ++inner;
        continue;
      }
      for (uint32_t i = n.child[c], end = n.child[c] + n.count[c]; i < end; ++i) {
        const BvhPrimitive& p = bvh.primitives[i];
        float t, u = 0, v = 0;
        const bool h = p.geom == bvh.sphere_geom ? bvh_sphere_hit(p, ray, tmin, tmax, t) : bvh_triangle_hit(p, ray, tmin, tmax, t, u, v);
        if (!h) continue;
        if (any_hit) return true;
        found = true;
        tmax = t;
        hit->t = t, hit->geom = p.geom, hit->prim = p.prim, hit->u = u, hit->v = v;
      }
    }
    if (inner == 2) {  // nearer child first; the farther waits on the stack
      const int near = enter[1] < enter[0] ? 1 : 0;
      stack[sp] = next[1 - near], stack_t[sp] = enter[1 - near], ++sp;
      node = next[near];
    } else if (inner == 1) {
      node = next[0];
    } else {  // pop, skipping boxes a closer hit found since has put out of reach
      do {
        if (sp == 0) return found;
        --sp;
      } while (stack_t[sp] > tmax);
      node = stack[sp];
    }
  }
}

// The ray tracer the per-pixel stages take (di_pixel.h's Tracer) over this traversal: the CUDA
// backend's kernels use it, and the host can run the same stages on the same BVH.
struct BvhTracer {
  BvhView bvh;
  RayCounter rays{};  // each query counted while the frame counts them (core/ray_counter.h)
  RESTIR_HD bool occluded(const Ray& r) const {
    rays.add(true);
    return bvh_trace(bvh, r, true, nullptr);
  }
  RESTIR_HD bool intersect(const Ray& r, Hit& hit) const {
    rays.add(false);
    return bvh_trace(bvh, r, false, &hit);
  }
};

}  // namespace rl
