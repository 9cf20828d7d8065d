// The BVH the CUDA backend traverses (and the CPU traverses in tests, to prove the same code
// right against Embree): built on the host with Embree's generic SAH builder (rtcBuildBVH) into
// our own layout, flattened depth-first into two flat arrays that copy to a device as they are.
//
// Layout (Aila & Laine 2009, "Understanding the Efficiency of Ray Traversal on GPUs"): a binary
// tree whose node holds both children's boxes, so a thread tests two boxes per node fetch and
// never loads a child it will not enter. 64-byte nodes, 48-byte primitives (triangle vertices or
// sphere centre and radius, with the scene ids Hit reports).
//
// Or (render.bvh = wide) the compressed 8-wide tree of Ylitie, Karras & Laine 2017 (wide_bvh.h)
// over the same primitives, built by the same builder with eight children a node.
#pragma once
#include <cstdint>
#include <vector>

#include "backends/backend_error.h"
#include "backends/bvh_layout.h"
#include "backends/wide_bvh.h"
#include "core/math.h"
#include "scene/scene.h"

namespace rl {

// 16-byte aligned: a GPU thread loads a node in four 128-bit loads (the traversal copies it whole).
struct alignas(16) BvhNode {
  Vec3 lo[2], hi[2];   // the children's boxes
  uint32_t child[2];   // inner child: node index; leaf child: first primitive
  uint32_t count[2];   // 0: inner node (or no child when child == kBvhNone); > 0: leaf of count primitives
};
static_assert(sizeof(BvhNode) == 64);

inline constexpr uint32_t kBvhNone = 0xffffffffu;

struct BvhPrimitive {
  Vec3 a, b, c;        // triangle: its vertices; sphere: a = centre, b.x = radius
  uint32_t geom = 0;   // mesh index, or the sphere geometry (number of meshes) for spheres
  uint32_t prim = 0;   // triangle in the mesh, or sphere index
  uint32_t pad[1] = {0};
};
static_assert(sizeof(BvhPrimitive) == 48);

// The exact box of a primitive (sphere_geom: the geom id that marks spheres).
inline Bounds3 primitive_bounds(const BvhPrimitive& p, uint32_t sphere_geom) {
  if (p.geom == sphere_geom) return {p.a - Vec3(p.b.x), p.a + Vec3(p.b.x)};
  return {min(p.a, min(p.b, p.c)), max(p.a, max(p.b, p.c))};
}

// What a traversal sees: pointers into host or device memory (trivially copyable). One of nodes
// and wide_nodes is set (the tree's layout), or neither for an empty scene.
struct BvhView {
  const BvhNode* nodes = nullptr;
  const WideBvhNode* wide_nodes = nullptr;
  const BvhPrimitive* primitives = nullptr;
  uint32_t node_count = 0, primitive_count = 0;  // node_count: of the layout's nodes
  uint32_t sphere_geom = 0;  // geom id of spheres (= number of meshes, as Accel)
};

inline constexpr int kBvhMaxDepth = 48;  // the builder's depth limit; the traversal stack holds this many

struct Bvh {
  BvhLayout layout = BvhLayout::binary;
  std::vector<BvhNode> nodes;           // binary: nodes[0] is the root (none for an empty scene)
  std::vector<WideBvhNode> wide_nodes;  // wide: wide_nodes[0] is the root
  std::vector<BvhPrimitive> primitives; // in leaf order
  uint32_t sphere_geom = 0;
  int depth = 0;                        // of the deepest leaf (root = 1)
  uint32_t node_count() const { return uint32_t(layout == BvhLayout::wide ? wide_nodes.size() : nodes.size()); }
  size_t node_bytes() const { return nodes.size() * sizeof(BvhNode) + wide_nodes.size() * sizeof(WideBvhNode); }
  BvhView view() const {
    return {nodes.empty() ? nullptr : nodes.data(), wide_nodes.empty() ? nullptr : wide_nodes.data(), primitives.data(),
            node_count(), uint32_t(primitives.size()), sphere_geom};
  }
};

// SAH build over every triangle and sphere of the scene (its current pose), flattened into the
// layout's tree. Throws BackendError if Embree fails.
Bvh build_bvh(const Scene& scene, BvhLayout layout = BvhLayout::binary);

}  // namespace rl
