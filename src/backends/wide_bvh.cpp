// The compressed 8-wide BVH (wide_bvh.h) from Embree's 8-wide SAH tree: each builder node becomes
// one 80-byte node whose children are ordered per ray octant and whose boxes are quantized
// outwards onto the node's grid (Ylitie, Karras & Laine 2017, §3). The builder's own wide SAH
// split (it opens the child of largest area until a node has eight) stands in for the paper's
// optimal collapse of a binary tree.
#include <array>
#include <cmath>
#include <limits>

#include "backends/bvh_build.h"

namespace rl {

namespace {

using bvh_build::Node;

Bounds3 box_of(const RTCBounds& b) {
  Bounds3 r;
  r.lo = {b.lower_x, b.lower_y, b.lower_z};
  r.hi = {b.upper_x, b.upper_y, b.upper_z};
  return r;
}

// Octant s's diagonal, with the traversal's octant bits (x negative: 4, y: 2, z: 1).
Vec3 octant_direction(int s) { return {s & 4 ? -1.0f : 1.0f, s & 2 ? -1.0f : 1.0f, s & 1 ? -1.0f : 1.0f}; }

// The slot of each child (Ylitie et al. 2017, §3.1): child c in slot s costs how far along
// octant s's diagonal its centre lies from the node's, so a ray of octant s meets the child of
// slot s first. The paper solves the assignment with an auction; the cheapest free (child, slot)
// pair first is within a few percent of it and needs no tuning.
std::array<int, kWideBvhWidth> assign_slots(const Bounds3* boxes, int n, const Bounds3& node) {
  float cost[kWideBvhWidth][kWideBvhWidth];
  const Vec3 centre = (node.lo + node.hi) * 0.5f;
  for (int c = 0; c < n; ++c)
    for (int s = 0; s < kWideBvhWidth; ++s) cost[c][s] = dot((boxes[c].lo + boxes[c].hi) * 0.5f - centre, octant_direction(s));
  std::array<int, kWideBvhWidth> slot_of;
  slot_of.fill(-1);
  bool slot_taken[kWideBvhWidth] = {};
  for (int assigned = 0; assigned < n; ++assigned) {
    int best_c = -1, best_s = -1;
    for (int c = 0; c < n; ++c)
      for (int s = 0; s < kWideBvhWidth; ++s)
        if (slot_of[size_t(c)] < 0 && !slot_taken[s] && (best_c < 0 || cost[c][s] < cost[best_c][best_s])) best_c = c, best_s = s;
    slot_of[size_t(best_c)] = best_s, slot_taken[best_s] = true;
  }
  return slot_of;
}

// Grid coordinates of [lo, hi] on one axis of a grid (origin p, step 2^e), rounded outwards so
// that the decoded floats (wide_bvh_decode) hold the exact bounds. False when the 8 bits cannot.
bool quantize(float p, int8_t e, float lo, float hi, uint8_t& qlo, uint8_t& qhi) {
  const float step = wide_bvh_step(e);
  double l = std::clamp(std::floor((double(lo) - double(p)) / double(step)), 0.0, 255.0);
  while (l > 0 && wide_bvh_decode(p, step, uint8_t(l)) > lo) l -= 1;
  double h = std::clamp(std::ceil((double(hi) - double(p)) / double(step)), 0.0, 255.0);
  while (h < 255 && wide_bvh_decode(p, step, uint8_t(h)) < hi) h += 1;
  qlo = uint8_t(l), qhi = uint8_t(h);
  return wide_bvh_decode(p, step, qlo) <= lo && wide_bvh_decode(p, step, qhi) >= hi;
}

// The smallest exponent whose 255 steps span `extent` (the paper's e_i = ceil(log2(extent/255))).
int smallest_exponent(float extent) {
  if (!(extent > 0)) return -126;
  int k;
  const double m = std::frexp(double(extent) / 255.0, &k);  // extent / 255 = m 2^k, 0.5 <= m < 1
  return std::clamp(m == 0.5 ? k - 1 : k, -126, 127);
}

struct WideFlattener {
  const std::vector<BvhPrimitive>& source;
  Bvh& out;

  // Writes the node at `at` (already reserved) over the children kids[0, n), then the inner
  // children's own nodes, depth-first.
  void node(const Node* const* kids, const Bounds3* boxes, int n, uint32_t at, int depth) {
    if (depth > kBvhMaxDepth) throw BackendError("BVH deeper than the traversal stack allows");
    out.depth = std::max(out.depth, depth);
    Bounds3 all;
    for (int c = 0; c < n; ++c) all.extend(boxes[c].lo), all.extend(boxes[c].hi);
    WideBvhNode w{};
    w.origin = all.lo;
    uint8_t lo_q[kWideBvhWidth][3] = {}, hi_q[kWideBvhWidth][3] = {};
    quantize_boxes(w, boxes, n, all, lo_q, hi_q);
    const std::array<int, kWideBvhWidth> slot_of = assign_slots(boxes, n, all);
    int child_in[kWideBvhWidth];
    std::fill(child_in, child_in + kWideBvhWidth, -1);
    for (int c = 0; c < n; ++c) child_in[slot_of[size_t(c)]] = c;
    // Inner children contiguous in slot order, then the leaves' primitives in slot order.
    w.child_base = uint32_t(out.wide_nodes.size());
    w.primitive_base = uint32_t(out.primitives.size());
    uint32_t inner = 0;
    for (int s = 0; s < kWideBvhWidth; ++s) {
      const int c = child_in[s];
      if (c < 0) continue;
      w.lo[0][s] = lo_q[c][0], w.lo[1][s] = lo_q[c][1], w.lo[2][s] = lo_q[c][2];
      w.hi[0][s] = hi_q[c][0], w.hi[1][s] = hi_q[c][1], w.hi[2][s] = hi_q[c][2];
      if (!kids[c]->leaf) {
        w.inner_mask |= uint8_t(1u << s);
        w.meta[s] = uint8_t((1u << 5) | (24u + uint32_t(s)));
        ++inner;
        continue;
      }
      const unsigned count = kids[c]->count;
      if (count < 1 || count > unsigned(kWideBvhMaxLeaf)) throw BackendError("BVH leaf larger than a wide node's leaf holds");
      const uint32_t offset = uint32_t(out.primitives.size()) - w.primitive_base;
      w.meta[s] = uint8_t((((1u << count) - 1) << 5) | offset);
      for (unsigned i = 0; i < count; ++i) out.primitives.push_back(source[kids[c]->prims[i]]);
      out.depth = std::max(out.depth, depth + 1);
    }
    out.wide_nodes[at] = w;
    out.wide_nodes.resize(out.wide_nodes.size() + inner);
    uint32_t next = w.child_base;
    for (int s = 0; s < kWideBvhWidth; ++s) {
      const int c = child_in[s];
      if (c < 0 || kids[c]->leaf) continue;
      Bounds3 grand[kWideBvhWidth];
      const Node& k = *kids[c];
      for (unsigned j = 0; j < k.children; ++j) grand[j] = box_of(k.bounds[j]);
      node(k.child, grand, int(k.children), next++, depth + 1);
    }
  }

  // The node's grid (an exponent per axis; a coarser step where float rounding would put a
  // decoded corner inside the exact one) and each child's coordinates on it.
  static void quantize_boxes(WideBvhNode& w, const Bounds3* boxes, int n, const Bounds3& all, uint8_t (*lo_q)[3], uint8_t (*hi_q)[3]) {
    for (int axis = 0; axis < 3; ++axis) {
      int e = smallest_exponent(all.hi[axis] - all.lo[axis]);
      for (;; ++e) {
        bool ok = true;
        for (int c = 0; c < n && ok; ++c) ok = quantize(all.lo[axis], int8_t(e), boxes[c].lo[axis], boxes[c].hi[axis], lo_q[c][axis], hi_q[c][axis]);
        if (ok) break;
        if (e >= 127) throw BackendError("a BVH node's boxes cannot be quantized (non-finite bounds?)");
      }
      w.exponent[axis] = int8_t(e);
    }
  }
};

}  // namespace

void flatten_wide(const Node& root, const std::vector<BvhPrimitive>& prims, Bvh& bvh) {
  bvh.wide_nodes.reserve(prims.size() / 4 + 1);
  bvh.primitives.reserve(prims.size());
  bvh.wide_nodes.emplace_back();
  WideFlattener f{prims, bvh};
  if (root.leaf) {  // a whole scene in one leaf: a root with that leaf as its one child
    const Node* kid = &root;
    const Bounds3 b = bvh_build::bounds_of(prims, bvh.sphere_geom);
    f.node(&kid, &b, 1, 0, 1);
    return;
  }
  Bounds3 boxes[kWideBvhWidth];
  for (unsigned j = 0; j < root.children; ++j) boxes[j] = box_of(root.bounds[j]);
  f.node(root.child, boxes, int(root.children), 0, 1);
}

}  // namespace rl
