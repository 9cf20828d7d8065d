// Which tree the project's own BVH (bvh.h) is flattened into: a render option (render.bvh), so it
// sits in this small header that options.h can include without the BVH itself.
#pragma once

namespace rl {

// binary: Aila & Laine 2009's two-box nodes, traversed nearer child first with a stack of the
// far ones and their distances. wide: Ylitie, Karras & Laine 2017's compressed 8-wide nodes
// (child boxes quantized to 8 bits an axis, children ordered per ray octant, a compressed stack
// of node and primitive groups; wide_bvh.h).
enum class BvhLayout { binary, wide };

}  // namespace rl
