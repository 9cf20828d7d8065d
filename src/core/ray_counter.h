// Ray counters (issue 48: "measure before redesigning"): how many closest-hit and any-hit queries
// each stage of a frame traces, on every backend. The per-pixel stages count through their tracer
// (frame_world.h's Tracer holds a RayCounter); the queue stages (a wavefront's trace_closest /
// trace_any, the primary hits) add a whole queue at once on the host (RayTally). StageTimer reads
// a backend's running totals before and after each stage (stage_times.h). The counts are sums of
// integers, so they do not depend on the thread count or schedule.
#pragma once
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>

#include "core/math.h"

namespace rl {

struct RayCounts {
  uint64_t closest = 0;  // closest-hit queries
  uint64_t any = 0;      // any-hit (shadow, visibility) queries
  // Of the any-hit queries, those a reuse pass queued and one stage traced for it (render.reuse_rays
  // = queued, frame/ray_slots.h); the rest each pixel's thread traced itself.
  uint64_t queued = 0;
  uint64_t total() const { return closest + any; }
  RayCounts& operator+=(const RayCounts& o) {
    closest += o.closest, any += o.any, queued += o.queued;
    return *this;
  }
  friend RayCounts operator+(RayCounts a, const RayCounts& b) { return a += b; }
  friend RayCounts operator-(const RayCounts& a, const RayCounts& b) {
    return {a.closest - b.closest, a.any - b.any, a.queued - b.queued};
  }
  friend bool operator==(const RayCounts&, const RayCounts&) = default;
};

// The counter slots: kRaySlots cache lines, each holding [closest, any, queued]. On the host, each of the
// first kRaySlots - 1 threads that count owns one (no other thread writes it, so a plain
// increment is safe: the readers read after the stage's threads joined), and every later thread
// shares the last one through atomics; on the device, blocks share slots through warp-aggregated
// atomics. 65 x 64 bytes.
inline constexpr uint32_t kRaySlots = 65, kRaySlotStride = 8;  // uint64 per slot: one 64-byte line
inline constexpr size_t kRaySlotWords = size_t(kRaySlots) * kRaySlotStride;

#ifndef __CUDA_ARCH__
// This host thread's slot, numbered in the order threads first count: its own for the first
// kRaySlots - 1 threads of the process, the shared last one after them. Zero-initialized thread
// storage (no guard on the hot path): 0 means not numbered yet.
inline uint32_t host_ray_slot() {
  static std::atomic<uint32_t> next{0};
  thread_local uint32_t slot_plus_one = 0;
  if (slot_plus_one == 0) slot_plus_one = std::min(next.fetch_add(1, std::memory_order_relaxed), kRaySlots - 1) + 1;
  return slot_plus_one - 1;
}
#endif

// What a per-pixel stage's tracer counts into: kRaySlotWords words in the execution policy's
// memory (host or device), or nothing (slots null: not counting).
struct RayCounter {
  uint64_t* slots = nullptr;

  // A query of one kind: closest hit or any hit.
  RESTIR_HD void add(bool any_hit) const { add_word(any_hit ? 1u : 0u); }
  // An any-hit query a reuse pass queued (counted besides its add(true)).
  RESTIR_HD void add_queued() const { add_word(2u); }
  // word: 0 closest, 1 any, 2 queued.
  RESTIR_HD void add_word(uint32_t word) const {
    if (!slots) return;
#if defined(__CUDA_ARCH__)
    // One atomic per warp and kind: the lanes counting together elect their lowest lane, which
    // adds their number (a relaxed global atomic per ray would queue a warp's 32 on one address).
    const unsigned active = __activemask();
    const unsigned peers = __match_any_sync(active, word);
    unsigned lane;
    asm("mov.u32 %0, %%laneid;" : "=r"(lane));
    if (lane == unsigned(__ffs(peers) - 1)) {
      const uint32_t slot = (blockIdx.x + blockIdx.y * gridDim.x) % kRaySlots;
      atomicAdd(reinterpret_cast<unsigned long long*>(slots + slot * kRaySlotStride + word),
                static_cast<unsigned long long>(__popc(peers)));
    }
#else
    const uint32_t slot = host_ray_slot();
    uint64_t* c = slots + slot * kRaySlotStride + word;
    if (slot < kRaySlots - 1) {
      __atomic_store_n(c, __atomic_load_n(c, __ATOMIC_RELAXED) + 1, __ATOMIC_RELAXED);  // its own slot: no lock
    } else {
      __atomic_fetch_add(c, uint64_t(1), __ATOMIC_RELAXED);  // the shared slot of the threads past the first 64
    }
#endif
  }
};

// The sum over the slots (host memory: a device policy downloads them first).
inline RayCounts sum_ray_slots(const uint64_t* slots) {
  RayCounts c;
  for (uint32_t s = 0; s < kRaySlots; ++s)
    c.closest += slots[s * kRaySlotStride], c.any += slots[s * kRaySlotStride + 1], c.queued += slots[s * kRaySlotStride + 2];
  return c;
}

// Whole queues counted on the host (a wavefront's trace_closest / trace_any, primary hits).
struct RayTally {
  std::atomic<uint64_t> closest{0}, any{0};
  void add(uint64_t n, bool any_hit) { (any_hit ? any : closest).fetch_add(n, std::memory_order_relaxed); }
  RayCounts counts() const { return {closest.load(std::memory_order_relaxed), any.load(std::memory_order_relaxed)}; }
};

}  // namespace rl
