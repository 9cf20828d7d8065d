// The CPU backend of the frames (ARCHITECTURE.md, "Backends"): the host execution policy (oneTBB
// threads over 16x16-pixel tiles), Embree for the per-pixel stages' rays (EmbreeTracer, one ray at
// a time) and, for the primary hits, Embree's coherent 16x16-ray streams (build_gbuffer). The
// world is the host's scene itself: no copy. The reference backend: the others agree with it in
// distribution (tests/frame/test_backends.cpp).
//
// A backend B gives each algorithm's frame (reservoir_chain.h and the <algo>_frame.h files):
//   B::Exec                     the execution policy (host_exec.h documents it)
//   B::Tracer                   the stages' ray queries (frame_world.h)
//   B::World                    update(ctx, frame) before each frame; view(): its FrameWorld
//   B::primary_hits(world, ctx, frame, sample, pixels, emitted, motion)   the G-buffer of one pixel sample
//   B::trace_closest(world, rays, hits, n, coherent)   a queue of rays: closest hits, no shading
//   B::trace_any(world, rays, blocked, n)              a queue of rays: any hit (shadow rays)
//   world.ray_totals()          the rays traced through the world so far, while frames count them
//                               (core/ray_counter.h: a frame counts when it records stage times)
#pragma once
#include <memory>
#include <span>
#include <vector>

#include "backends/cpu/embree_tracer.h"
#include "backends/cpu/host_exec.h"
#include "frame/frame_world.h"
#include "frame/gbuffer.h"

namespace rl {

struct CpuBackend {
  using Exec = HostExec;
  using Tracer = EmbreeTracer;

  class World {
   public:
    // Views of ctx's scene, lights and Embree BVH, and of the previous frame's that `frame` carries.
    void update(const RenderContext& ctx, const FrameInfo& frame);
    const FrameWorld<Tracer>& view() const { return fw_; }
    // The rays traced so far: the tracers' (per-pixel stages) and the queues' (tally).
    RayCounts ray_totals() const { return sum_ray_slots(slots_.get()) + tally_.counts(); }
    RayTally& tally() const { return tally_; }

   private:
    std::unique_ptr<uint64_t[]> slots_ = std::make_unique<uint64_t[]>(kRaySlotWords);  // zeroed
    mutable RayTally tally_;
    FrameWorld<Tracer> fw_;
    std::vector<Mat4> back_, forward_;
    bool animated_known_ = false;
  };

  // Sample `sample`'s primary hits of every pixel into pixels[] and (unless null) motion[].
  static void primary_hits(const World& w, const RenderContext& ctx, const FrameInfo& frame, int sample, GPacked* pixels,
                           Rgb* emitted, GMotion* motion) {
    const FrameWorld<Tracer>& fw = w.view();
    build_gbuffer(ctx, *frame.camera, frame.index, sample, fw.back, fw.animation_count, pixels, emitted, motion);
    w.tally().add(uint64_t(frame.camera->width()) * uint64_t(frame.camera->height()), false);  // a camera ray a pixel
  }
  // Embree's stream queries over parallel chunks of the queue; `coherent` (camera rays) lets it
  // trace them as packets.
  static void trace_closest(const World& w, const Ray* rays, Hit* hits, size_t n, bool coherent) {
    w.view().tracer.accel->intersect_batch(std::span<const Ray>(rays, n), std::span<Hit>(hits, n), coherent);
    w.tally().add(n, false);
  }
  static void trace_any(const World& w, const Ray* rays, uint8_t* blocked, size_t n) {
    w.view().tracer.accel->occluded_batch(std::span<const Ray>(rays, n), std::span<uint8_t>(blocked, n));
    w.tally().add(n, true);
  }
};

// Per animation: the inverse of each of motion_back's maps (the identity where one is singular).
std::vector<Mat4> motion_forward(const std::vector<Mat4>& back);

}  // namespace rl
