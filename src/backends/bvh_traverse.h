// Closest-hit and any-hit traversal of a Bvh (bvh.h; either layout), the same code on the host (tests, against
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
// min and max of slab distances, which are never NaN (a queryable ray's origin and t range are
// finite, 1/d is finite and nonzero): plain comparisons, which compile to one instruction on the
// host too, where fminf / fmaxf keep their NaN rules in a library call.
RESTIR_HD inline float bvh_min(float a, float b) { return a < b ? a : b; }
RESTIR_HD inline float bvh_max(float a, float b) { return a > b ? a : b; }

// (x - o) / d rounds monotonically in x, so each axis' near face is lo where 1/d > 0 and hi where it
// is < 0: the same t's that sorting the two faces' would give, without six more min/max.
RESTIR_HD inline bool bvh_box_hit(Vec3 lo, Vec3 hi, Vec3 o, Vec3 inv_d, float tmin, float tmax, float& t_enter) {
  const bool px = inv_d.x >= 0, py = inv_d.y >= 0, pz = inv_d.z >= 0;
  const float t0 = bvh_max(bvh_max(((px ? lo.x : hi.x) - o.x) * inv_d.x, ((py ? lo.y : hi.y) - o.y) * inv_d.y),
                           bvh_max(((pz ? lo.z : hi.z) - o.z) * inv_d.z, tmin));
  const float t1 = bvh_min(bvh_min(((px ? hi.x : lo.x) - o.x) * inv_d.x, ((py ? hi.y : lo.y) - o.y) * inv_d.y),
                           bvh_min(((pz ? hi.z : lo.z) - o.z) * inv_d.z, tmax));
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

// Tests primitive i of the BVH against the ray in [tmin, tmax]. On a hit, a closest-hit query
// (hit != null) narrows tmax to it and records it; an any-hit query (hit == null) only learns it.
RESTIR_HD inline bool bvh_primitive_hit(const BvhView& bvh, uint32_t i, const Ray& ray, float tmin, float& tmax, Hit* hit) {
  const BvhPrimitive& p = bvh.primitives[i];
  float t, u = 0, v = 0;
  const bool h = p.geom == bvh.sphere_geom ? bvh_sphere_hit(p, ray, tmin, tmax, t) : bvh_triangle_hit(p, ray, tmin, tmax, t, u, v);
  if (!h) return false;
  if (hit) tmax = t, hit->t = t, hit->geom = p.geom, hit->prim = p.prim, hit->u = u, hit->v = v;
  return true;
}

// 1 / d with zeros replaced by a huge value of the same sign (bvh_box_hit).
RESTIR_HD inline Vec3 bvh_inverse_direction(Vec3 d) {
  auto safe_inv = [](float x) { return std::fabs(x) > 1e-30f ? 1.0f / x : std::copysign(1e30f, x); };
  return {safe_inv(d.x), safe_inv(d.y), safe_inv(d.z)};
}

// Wide layout (Ylitie, Karras & Laine 2017, §4 and Algorithm 1): a node's hit children become
// one 32-bit mask (wide_bvh.h's meta), and the stack holds (base, mask) groups of nodes still to
// visit instead of nodes. The inner child of the highest bit goes first: for a ray of octant o
// that is slot o, the child the build put first along o's diagonal. A leaf's primitives are
// tested as soon as their node is (the paper may postpone them to keep a warp's lanes together;
// the hits are the same).
struct WideBvhGroup {
  uint32_t base = 0;  // nodes: the first inner child; primitives: the first primitive
  uint32_t mask = 0;  // nodes: hit bits 24-31 and the parent's inner mask in 0-7; primitives: bits 0-23
};

RESTIR_HD inline int wide_bvh_highest_bit(uint32_t x) {
#ifdef __CUDA_ARCH__
  return 31 - __clz(x);
#else
  return 31 - __builtin_clz(x);
#endif
}

RESTIR_HD inline uint32_t wide_bvh_popcount(uint32_t x) {
#ifdef __CUDA_ARCH__
  return uint32_t(__popc(x));
#else
  return uint32_t(__builtin_popcount(x));
#endif
}

// The children of node n the ray enters within [tmin, tmax], as a hit mask (wide_bvh.h). The ray
// is moved onto the node's grid once (the paper's §4: a plane q 2^e + p is crossed at
// t = q (2^e / d) + (p - o) / d), so a child's six planes cost a multiply-add each; and since
// q -> q (2^e / d) + (p - o) / d is monotone in float arithmetic too, the near plane of each axis
// is the low one where 1/d > 0 and the high one where 1/d < 0 -- no min and max to sort them, the
// same t's as sorting would give.
RESTIR_HD inline uint32_t wide_bvh_node_hits(const WideBvhNode& n, const Ray& ray, Vec3 inv_d, float tmin, float tmax, uint32_t oct_inv) {
  const Vec3 scale{wide_bvh_step(n.exponent[0]) * inv_d.x, wide_bvh_step(n.exponent[1]) * inv_d.y, wide_bvh_step(n.exponent[2]) * inv_d.z};
  const Vec3 shift{(n.origin.x - ray.o.x) * inv_d.x, (n.origin.y - ray.o.y) * inv_d.y, (n.origin.z - ray.o.z) * inv_d.z};
  // oct_inv's bits are set where inv_d > 0 (x: 4, y: 2, z: 1). The faces are chosen by value, not
  // through a pointer to n.lo or n.hi: an indexed pointer would put the node in a GPU thread's
  // local memory instead of its registers (the PTX's local loads and stores went 32 -> 138).
  const bool px = oct_inv & 4u, py = oct_inv & 2u, pz = oct_inv & 1u;
  uint32_t hits = 0;
  for (uint32_t s = 0; s < uint32_t(kWideBvhWidth); ++s) {
    const uint32_t meta = n.meta[s];
    if (meta == 0) continue;
    const float qnx = px ? n.lo[0][s] : n.hi[0][s], qfx = px ? n.hi[0][s] : n.lo[0][s];
    const float qny = py ? n.lo[1][s] : n.hi[1][s], qfy = py ? n.hi[1][s] : n.lo[1][s];
    const float qnz = pz ? n.lo[2][s] : n.hi[2][s], qfz = pz ? n.hi[2][s] : n.lo[2][s];
    const float t0 = bvh_max(bvh_max(qnx * scale.x + shift.x, qny * scale.y + shift.y), bvh_max(qnz * scale.z + shift.z, tmin));
    const float t1 = bvh_min(bvh_min(qfx * scale.x + shift.x, qfy * scale.y + shift.y), bvh_min(qfz * scale.z + shift.z, tmax));
    if (!(t0 <= t1 * 1.00000024f)) continue;
    // Inner: one bit at 24 + (s ^ oct_inv); leaf: its primitives' bits from its offset.
    const uint32_t bit = (meta & 31u) ^ ((n.inner_mask >> s) & 1u ? oct_inv : 0u);
    hits |= (meta >> 5) << bit;
  }
  return hits;
}

RESTIR_HD inline bool wide_bvh_trace(const BvhView& bvh, const Ray& ray, bool any_hit, Hit* hit) {
  const Vec3 inv_d = bvh_inverse_direction(ray.d);
  // The octant by inv_d's signs, not d's: a -0 component has inv_d = -1e30 (bvh_inverse_direction),
  // and wide_bvh_node_hits picks each axis' near plane by this sign.
  const uint32_t oct_inv = 7u - ((inv_d.x < 0 ? 4u : 0u) | (inv_d.y < 0 ? 2u : 0u) | (inv_d.z < 0 ? 1u : 0u));
  const float tmin = ray.tmin;
  float tmax = ray.tmax;
  bool found = false;
  WideBvhGroup stack[kBvhMaxDepth + 2];  // a group a level at most: the tree is at most kBvhMaxDepth deep
  int sp = 0;
  WideBvhGroup nodes{0, 1u << 31};  // the root: bit 31 with an empty inner mask is index 0
  WideBvhGroup prims{};
  for (;;) {
    while (prims.mask != 0) {
      const int b = wide_bvh_highest_bit(prims.mask);
      prims.mask &= ~(1u << b);
      if (!bvh_primitive_hit(bvh, prims.base + uint32_t(b), ray, tmin, tmax, any_hit ? nullptr : hit)) continue;
      if (any_hit) return true;
      found = true;
    }
    if ((nodes.mask & 0xff000000u) == 0) {
      if (sp == 0) return found;
      nodes = stack[--sp];
    }
    const int b = wide_bvh_highest_bit(nodes.mask);
    nodes.mask &= ~(1u << b);
    const uint32_t slot = uint32_t(b - 24) ^ oct_inv;
    // The inner children before this slot in the parent come before it in memory.
    const uint32_t index = nodes.base + wide_bvh_popcount(nodes.mask & 0xffu & ((1u << slot) - 1u));
    if (nodes.mask & 0xff000000u) stack[sp++] = nodes;
    const WideBvhNode n = bvh.wide_nodes[index];  // whole: five 128-bit loads on the GPU, not 40 byte loads
    const uint32_t hits = wide_bvh_node_hits(n, ray, inv_d, tmin, tmax, oct_inv);
    nodes = {n.child_base, (hits & 0xff000000u) | n.inner_mask};
    prims = {n.primitive_base, hits & 0x00ffffffu};
  }
}

// Binary layout: iterative, nearer child first, with a stack of the far children (kBvhMaxDepth
// deep) and where the ray enters them.
RESTIR_HD inline bool binary_bvh_trace(const BvhView& bvh, const Ray& ray, bool any_hit, Hit* hit) {
  const Vec3 inv_d = bvh_inverse_direction(ray.d);
  const float tmin = ray.tmin;
  float tmax = ray.tmax;
  bool found = false;
  uint32_t stack[kBvhMaxDepth + 2];   // the farther children not yet visited ...
  float stack_t[kBvhMaxDepth + 2];    // ... and where the ray enters their boxes
  int sp = 0;
  uint32_t node = 0;
  for (;;) {
    const BvhNode n = bvh.nodes[node];  // whole: four 128-bit loads on the GPU
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
        if (!bvh_primitive_hit(bvh, i, ray, tmin, tmax, any_hit ? nullptr : hit)) continue;
        if (any_hit) return true;
        found = true;
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

// Closest hit (any_hit = false) or any hit (true: returns at the first) in either layout. hit
// is written only on a closest hit.
RESTIR_HD inline bool bvh_trace(const BvhView& bvh, const Ray& ray, bool any_hit, Hit* hit) {
  if (bvh.node_count == 0 || !ray_queryable(ray)) return false;
  if (bvh.wide_nodes) return wide_bvh_trace(bvh, ray, any_hit, hit);
  return binary_bvh_trace(bvh, ray, any_hit, hit);
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
