// The compressed 8-wide BVH node of Ylitie, Karras & Laine 2017 ("Efficient Incoherent Ray
// Traversal on GPUs Through Compressed Wide BVHs", HPG; §3.2 and fig. 3): 80 bytes for eight
// children, where the binary layout (bvh.h) spends 64 on two.
//
// - The children's boxes are stored on a grid local to the node: origin p, a step of 2^e_i on
//   axis i (e_i the smallest exponent whose 255 steps span the node), and each box as the 8-bit
//   grid coordinates of its corners, rounded outwards (a decoded box always holds the exact one).
// - A node's inner children are contiguous from child_base and its leaves' primitives contiguous
//   from primitive_base, both in slot order, so eight children cost two indices.
// - meta[s] says what slot s holds: 0 nothing; an inner node 0b001'11sss (24 + s in the low five
//   bits); a leaf of c <= 3 primitives c ones in the high three bits (0b001, 0b011, 0b111) and the
//   offset of its first primitive from primitive_base (< 24) in the low five. A node's hits are
//   then one 32-bit mask: a leaf sets the bits of its primitives (0-23), an inner child the bit
//   24 + (s ^ octant mask) -- the traversal's compressed stack holds (base, mask) pairs, not nodes.
// - Slots are assigned per ray octant (the paper's §3.1): the child in slot s is the one that
//   comes first along directions of octant s (wide_bvh.cpp), so taking the highest inner bit
//   first visits children roughly near to far without sorting.
#pragma once
#include <cstdint>

#include "core/math.h"

namespace rl {

// 16-byte aligned: a GPU thread loads a node in five 128-bit loads (wide_bvh_trace copies it whole).
struct alignas(16) WideBvhNode {
  Vec3 origin;              // p: the grid's corner (the node's box's lower corner)
  int8_t exponent[3];       // e: the grid step on each axis is 2^e
  uint8_t inner_mask;       // imask: bit s set when slot s holds an inner node
  uint32_t child_base;      // the first inner child (nodes index)
  uint32_t primitive_base;  // the first primitive of the leaves (primitives index)
  uint8_t meta[8];
  uint8_t lo[3][8], hi[3][8];  // per axis, per slot: the box's grid coordinates
};
static_assert(sizeof(WideBvhNode) == 80);

inline constexpr int kWideBvhWidth = 8;
inline constexpr int kWideBvhMaxLeaf = 3;  // a leaf's count is unary in meta's three high bits

// 2^e as a float, for -126 <= e <= 127 (the build keeps exponents there).
RESTIR_HD inline float wide_bvh_step(int8_t e) {
  const uint32_t bits = uint32_t(int(e) + 127) << 23;
#ifdef __CUDA_ARCH__
  return __uint_as_float(bits);
#else
  float f;
  __builtin_memcpy(&f, &bits, sizeof f);
  return f;
#endif
}

// A child box's corner on axis `axis` from its grid coordinate: q * 2^e is exact (q has 8 bits),
// so p + q * 2^e rounds once, with or without a fused multiply-add; the build checks that this
// float is on the outer side of the exact corner.
RESTIR_HD inline float wide_bvh_decode(float origin, float step, uint8_t q) { return origin + float(q) * step; }

}  // namespace rl
