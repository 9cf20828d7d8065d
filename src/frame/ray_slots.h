// The reuse passes' shadow rays as producer -> trace -> consumer (issue 48; render.reuse_rays =
// queued; docs/gpu.md, "The reuse passes' shadow rays in one kernel").
//
// Inline, each thread of the temporal or spatial pass traverses the BVH for every visibility test
// its shifts and MIS weights make, and the threads of a warp that are traversing leave the others
// idle. Queued, the pass runs each pixel twice, with the same inputs:
//   1. the producer records each any-hit ray in the pixel's slot j (j = the call's order) and
//      answers "unoccluded"; its outputs are thrown away;
//   2. one stage traces every recorded ray (a kernel of one any-hit query per thread: no shading,
//      every thread busy);
//   3. the consumer -- the pass itself -- answers its j-th any-hit query from slot j where that
//      slot holds the very same ray (bit for bit), else from another slot that does, and traces
//      it inline where none does.
// An answer is a function of the ray alone, so the consumer computes what the inline pass computes,
// bit for bit, whatever the producer recorded. What the producer predicts well is what makes it
// pay: with pairwise or generalized-balance MIS the queries a pixel makes follow from its inputs,
// not from the answers, so the consumer finds them all recorded; a pass whose queries depend on
// an answer (1/Z's last loop reads the selected sample) traces its unrecorded few itself.
// Closest-hit queries (ReSTIR GI's and PT's replays) stay inline in both runs.
#pragma once
#include <cstdint>

#include "core/math.h"
#include "core/rng.h"
#include "restir/mis.h"
#include "scene/ray_queries.h"

namespace rl {

// Where the producer writes: per pixel p, slots [p * per_pixel, (p + 1) * per_pixel).
// counts[p]: the any-hit queries the producer made (those past per_pixel were not recorded).
struct RaySlotsView {
  Ray* rays = nullptr;
  uint8_t* answers = nullptr;  // the trace stage's: 1 occluded, 0 not
  uint32_t* counts = nullptr;
  uint32_t per_pixel = 0;
};

// Slots a pixel of a pass combining `inputs` reservoirs with `kind` needs: pairwise and the ratio
// weights trace at most two shadow rays per neighbour (its sample at the canonical pixel and the
// canonical sample at the neighbour), generalized balance each sample at each other domain; one
// more for the canonical target some bridges re-evaluate (ReSTIR GI's visibility). Measured on
// the project's scenes (tests/frame/test_queued_rays.cpp): no pixel past these at the defaults.
// Capped at kMaxRaySlots: a pixel with more traces the rest inline.
inline constexpr uint32_t kMaxRaySlots = 32;
inline uint32_t ray_slots_per_pixel(restir::ReuseMis kind, int inputs) {
  const uint32_t n = uint32_t(inputs > 1 ? inputs : 1);
  const uint32_t want = (kind == restir::ReuseMis::generalized_balance ? n * (n - 1) : 2 * (n - 1)) + 1;
  return want < kMaxRaySlots ? want : kMaxRaySlots;
}

RESTIR_HD inline bool same_ray(const Ray& a, const Ray& b) {
  return float_bits(a.o.x) == float_bits(b.o.x) && float_bits(a.o.y) == float_bits(b.o.y) && float_bits(a.o.z) == float_bits(b.o.z) &&
         float_bits(a.d.x) == float_bits(b.d.x) && float_bits(a.d.y) == float_bits(b.d.y) && float_bits(a.d.z) == float_bits(b.d.z) &&
         float_bits(a.tmin) == float_bits(b.tmin) && float_bits(a.tmax) == float_bits(b.tmax);
}

// One pixel's run of a reuse pass through its slots: the producer (record) or the consumer.
struct RayCursor {
  RaySlotsView slots;
  uint32_t pixel = 0;
  bool record = false;
  uint32_t next = 0;  // the order of the pixel's next any-hit query
  RESTIR_HD size_t slot(uint32_t j) const { return size_t(pixel) * size_t(slots.per_pixel) + size_t(j); }
  template <class Tracer>
  RESTIR_HD bool occluded(const Tracer& tracer, const Ray& r) {
    const uint32_t j = next++;
    if (record) {
      if (j < slots.per_pixel) slots.rays[slot(j)] = r;
      return false;
    }
    const uint32_t recorded = slots.counts[pixel] < slots.per_pixel ? slots.counts[pixel] : slots.per_pixel;
    if (j < recorded && same_ray(slots.rays[slot(j)], r)) return slots.answers[slot(j)] != 0;
    // Where an answer changed what the pass does next (a shift that failed on an occluded ray makes
    // no more queries), the two runs' orders part: the ray may sit in another slot.
    for (uint32_t k = 0; k < recorded; ++k)
      if (k != j && same_ray(slots.rays[slot(k)], r)) return slots.answers[slot(k)] != 0;
    return tracer.occluded(r);  // a query the producer did not make
  }
  // The producer's end: how many queries it made.
  RESTIR_HD void finish() const {
    if (record) slots.counts[pixel] = next;
  }
};

// The tracer a reuse pass's bridge hands its shifts and targets when the pass is queued (cursor
// non-null): the frame's tracer, its any-hit queries through the pixel's cursor. An inline pass
// (cursor null) hands them the frame's tracer itself, so that it runs the code it ran before queues
// existed (on the CPU, the x86-64-v3 copies of ReSTIR PT's shifts, pt_path.cpp, are overloads for
// the plain tracer, and GCC inlines the plain instantiations as before).
template <class Tracer>
struct SlotTracer {
  const Tracer* inner;
  RayCursor* cursor;
  RESTIR_HD bool occluded(const Ray& r) const { return cursor ? cursor->occluded(*inner, r) : inner->occluded(r); }
  RESTIR_HD bool intersect(const Ray& r, Hit& hit) const { return inner->intersect(r, hit); }
};

// The tracer a bridge hands its shifts and targets: a queued pass's bridge (Queued) a SlotTracer
// through cursor (null: not queued, as for the previous frame's rays), an inline pass's the tracer
// itself. One tracer type per bridge type keeps nvcc's inlining of each as it was.
template <bool Queued, class Tracer>
RESTIR_HD decltype(auto) pass_tracer(const Tracer& tracer, RayCursor* cursor) {
  if constexpr (Queued) return SlotTracer<Tracer>{&tracer, cursor};
  else return (tracer);
}

// The trace stage: slot list[i]'s ray, its answer.
template <class Tracer>
struct TraceSlotsStage {
  Tracer tracer;
  RaySlotsView slots;
  const uint32_t* list;
  RESTIR_HD void operator()(size_t i) const {
    const uint32_t s = list[i];
    slots.answers[s] = tracer.occluded(slots.rays[s]) ? 1 : 0;
    tracer.rays.add_queued();
  }
};

// Which slots hold a recorded ray (the trace stage's list, Exec::select).
struct RecordedSlot {
  RaySlotsView slots;
  RESTIR_HD bool operator()(size_t s) const {
    const size_t p = s / slots.per_pixel;
    return uint32_t(s % slots.per_pixel) < slots.counts[p];
  }
};

}  // namespace rl
