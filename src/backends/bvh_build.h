// Inside the BVH builds (bvh.cpp, wide_bvh.cpp): the scene's primitives and Embree's generic SAH
// builder (rtcBuildBVH), whose tree lives in Embree's arenas while a flattener reads it.
#pragma once
#include <embree3/rtcore.h>

#include <functional>
#include <vector>

#include "backends/bvh.h"

namespace rl::bvh_build {

inline constexpr unsigned kMaxBranching = 8;

// The builder's own tree: an inner node holds its children and their boxes; a leaf, the indices
// of its primitives in the gathered list.
struct Node {
  bool leaf = false;
  unsigned children = 0;
  Node* child[kMaxBranching] = {};
  RTCBounds bounds[kMaxBranching]{};
  const unsigned* prims = nullptr;
  unsigned count = 0;
};

// Every triangle and sphere of the scene (its current pose) and its bounds for Embree
// (primID: its index in prims).
struct Primitives {
  std::vector<BvhPrimitive> prims;
  std::vector<RTCBuildPrimitive> refs;
};
Primitives gather_primitives(const Scene& scene, uint32_t sphere_geom);

// Runs the SAH builder over in.refs (consumed: the builder reorders it) with at most
// `branching` children a node and `max_leaf` primitives a leaf, and hands the root to `use`
// while the tree lives. Throws BackendError if Embree fails.
void build(Primitives& in, unsigned branching, unsigned max_leaf, const std::function<void(const Node&)>& use);

// The bounds of a whole scene in one leaf (a root that is a leaf: the flatteners give it a parent).
Bounds3 bounds_of(const std::vector<BvhPrimitive>& prims, uint32_t sphere_geom);

}  // namespace rl::bvh_build

namespace rl {
// The 8-wide compressed tree (wide_bvh.h) from the builder's tree over prims.
void flatten_wide(const bvh_build::Node& root, const std::vector<BvhPrimitive>& prims, Bvh& bvh);
}  // namespace rl
