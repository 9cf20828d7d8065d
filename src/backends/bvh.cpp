#include "backends/bvh.h"

#include <embree3/rtcore.h>

#include <stdexcept>
#include <string>

#include "backends/bvh_build.h"

namespace rl {

namespace bvh_build {

namespace {

void* create_node(RTCThreadLocalAllocator alloc, unsigned int children, void*) {
  if (children > kMaxBranching) return nullptr;
  void* mem = rtcThreadLocalAlloc(alloc, sizeof(Node), 16);
  Node* n = new (mem) Node();
  n->children = children;
  return n;
}

void set_children(void* node, void** children, unsigned int count, void*) {
  auto* n = static_cast<Node*>(node);
  for (unsigned i = 0; i < count && i < kMaxBranching; ++i) n->child[i] = static_cast<Node*>(children[i]);
}

void set_bounds(void* node, const RTCBounds** bounds, unsigned int count, void*) {
  auto* n = static_cast<Node*>(node);
  for (unsigned i = 0; i < count && i < kMaxBranching; ++i) n->bounds[i] = *bounds[i];
}

void* create_leaf(RTCThreadLocalAllocator alloc, const RTCBuildPrimitive* prims, size_t count, void*) {
  void* mem = rtcThreadLocalAlloc(alloc, sizeof(Node), 16);
  auto* n = new (mem) Node();
  auto* ids = static_cast<unsigned*>(rtcThreadLocalAlloc(alloc, sizeof(unsigned) * count, 4));
  for (size_t i = 0; i < count; ++i) ids[i] = prims[i].primID;
  n->leaf = true;
  n->prims = ids;
  n->count = unsigned(count);
  return n;
}

RTCBuildPrimitive build_primitive(const Bounds3& b, unsigned index) {
  RTCBuildPrimitive p;
  p.lower_x = b.lo.x, p.lower_y = b.lo.y, p.lower_z = b.lo.z, p.geomID = 0;
  p.upper_x = b.hi.x, p.upper_y = b.hi.y, p.upper_z = b.hi.z, p.primID = index;
  return p;
}

RTCBuildArguments build_arguments(RTCBVH handle, std::vector<RTCBuildPrimitive>& refs, unsigned branching, unsigned max_leaf) {
  RTCBuildArguments args = rtcDefaultBuildArguments();
  args.byteSize = sizeof(args);
  args.buildQuality = RTC_BUILD_QUALITY_HIGH;
  args.maxBranchingFactor = branching;
  args.maxDepth = kBvhMaxDepth;
  args.sahBlockSize = 1;
  args.minLeafSize = 1;
  args.maxLeafSize = max_leaf;
  // SAH costs for a SIMT traversal: a box pair per node fetch vs one primitive test (Aila &
  // Laine 2009 use roughly equal costs).
  args.traversalCost = 1.0f;
  args.intersectionCost = 1.0f;
  args.bvh = handle;
  args.primitives = refs.data();
  args.primitiveCount = refs.size();
  args.primitiveArrayCapacity = refs.size();  // no spatial splits: each primitive in one leaf
  args.createNode = create_node;
  args.setNodeChildren = set_children;
  args.setNodeBounds = set_bounds;
  args.createLeaf = create_leaf;
  return args;
}

}  // namespace

Primitives gather_primitives(const Scene& scene, uint32_t sphere_geom) {
  Primitives r;
  std::vector<BvhPrimitive>& prims = r.prims;
  std::vector<RTCBuildPrimitive>& refs = r.refs;
  prims.reserve(scene.triangle_count() + scene.spheres.size());
  refs.reserve(prims.capacity());
  for (uint32_t mi = 0; mi < scene.meshes.size(); ++mi) {
    const TriangleMesh& m = scene.meshes[mi];
    for (uint32_t t = 0; t < m.triangle_count(); ++t) {
      BvhPrimitive p;
      p.a = m.positions[m.indices[3 * t]], p.b = m.positions[m.indices[3 * t + 1]], p.c = m.positions[m.indices[3 * t + 2]];
      p.geom = mi, p.prim = t;
      refs.push_back(build_primitive(primitive_bounds(p, sphere_geom), unsigned(prims.size())));
      prims.push_back(p);
    }
  }
  for (uint32_t si = 0; si < scene.spheres.size(); ++si) {
    const Sphere& s = scene.spheres[si];
    BvhPrimitive p;
    p.a = s.center, p.b = Vec3(s.radius, 0, 0);
    p.geom = sphere_geom, p.prim = si;
    refs.push_back(build_primitive(primitive_bounds(p, sphere_geom), unsigned(prims.size())));
    prims.push_back(p);
  }
  return r;
}

Bounds3 bounds_of(const std::vector<BvhPrimitive>& prims, uint32_t sphere_geom) {
  Bounds3 b;
  for (const BvhPrimitive& p : prims) b.extend(primitive_bounds(p, sphere_geom));
  return b;
}

void build(Primitives& in, unsigned branching, unsigned max_leaf, const std::function<void(const Node&)>& use) {
  RTCDevice device = rtcNewDevice("threads=0");  // TBB's arena, as Accel
  if (!device) throw BackendError("cannot create the Embree device for the BVH build");
  RTCBVH handle = rtcNewBVH(device);
  RTCBuildArguments args = build_arguments(handle, in.refs, branching, max_leaf);
  void* root = rtcBuildBVH(&args);
  const RTCError err = rtcGetDeviceError(device);
  try {
    if (!root || err != RTC_ERROR_NONE)
      throw BackendError("Embree could not build the BVH (code " + std::to_string(int(err)) + ")");
    use(*static_cast<const Node*>(root));
  } catch (...) {
    rtcReleaseBVH(handle);
    rtcReleaseDevice(device);
    throw;
  }
  rtcReleaseBVH(handle);
  rtcReleaseDevice(device);
}

}  // namespace bvh_build

namespace {

using bvh_build::Node;

struct Flattener {
  const std::vector<BvhPrimitive>& source;
  Bvh& out;
  // Appends a leaf's primitives; returns the first.
  uint32_t leaf(const Node* n) {
    const uint32_t first = uint32_t(out.primitives.size());
    for (unsigned i = 0; i < n->count; ++i) out.primitives.push_back(source[n->prims[i]]);
    return first;
  }
  // Writes inner node n at index `at` (already reserved), children depth-first after it.
  void inner(const Node* n, uint32_t at, int depth) {
    if (depth > kBvhMaxDepth) throw BackendError("BVH deeper than the traversal stack allows");
    out.depth = std::max(out.depth, depth);
    for (int c = 0; c < 2; ++c) {
      BvhNode& slot = out.nodes[at];
      const Node* ch = n->child[c];
      if (!ch) {
        slot.child[c] = kBvhNone, slot.count[c] = 0;
        continue;
      }
      slot.lo[c] = {n->bounds[c].lower_x, n->bounds[c].lower_y, n->bounds[c].lower_z};
      slot.hi[c] = {n->bounds[c].upper_x, n->bounds[c].upper_y, n->bounds[c].upper_z};
      if (ch->leaf) {
        const uint32_t first = leaf(ch);
        out.nodes[at].child[c] = first, out.nodes[at].count[c] = ch->count;
        out.depth = std::max(out.depth, depth + 1);
      } else {
        const uint32_t index = uint32_t(out.nodes.size());
        out.nodes.emplace_back();
        out.nodes[at].child[c] = index, out.nodes[at].count[c] = 0;
        inner(ch, index, depth + 1);
      }
    }
  }
};

// The builder's tree (root r) into bvh's flat nodes and primitives.
void flatten(const Node* r, const std::vector<BvhPrimitive>& prims, Bvh& bvh) {
  bvh.nodes.reserve(prims.size());  // a binary tree over n leaves of >= 1 primitive has < n inner nodes
  bvh.primitives.reserve(prims.size());
  bvh.nodes.emplace_back();
  Flattener f{prims, bvh};
  if (r->leaf) {  // a whole scene in one leaf: a root with one leaf child
    bvh.nodes[0].child[1] = kBvhNone, bvh.nodes[0].count[1] = 0;
    const Bounds3 b = bvh_build::bounds_of(prims, bvh.sphere_geom);
    bvh.nodes[0].lo[0] = b.lo, bvh.nodes[0].hi[0] = b.hi;
    bvh.nodes[0].child[0] = f.leaf(r), bvh.nodes[0].count[0] = r->count;
    bvh.depth = 2;
  } else {
    f.inner(r, 0, 1);
  }
}

}  // namespace

Bvh build_bvh(const Scene& scene, BvhLayout layout) {
  Bvh bvh;
  bvh.layout = layout;
  bvh.sphere_geom = uint32_t(scene.meshes.size());
  bvh_build::Primitives in = bvh_build::gather_primitives(scene, bvh.sphere_geom);
  if (in.prims.empty()) return bvh;
  const bool wide = layout == BvhLayout::wide;
  bvh_build::build(in, wide ? kWideBvhWidth : 2, wide ? kWideBvhMaxLeaf : 4, [&](const Node& root) {
    if (wide) flatten_wide(root, in.prims, bvh);
    else flatten(&root, in.prims, bvh);
  });
  if (bvh.primitives.size() != in.prims.size()) throw BackendError("BVH build lost primitives");
  return bvh;
}

}  // namespace rl
