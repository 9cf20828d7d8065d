// The BVH backends of the frames: the project's own BVH (backends/bvh.h) traversed by the stages
// themselves (BvhTracer), over an execution policy -- the CUDA backend (cuda::CudaExec, device
// memory, one kernel per stage: cuda_backend.cuh) and its host twin (HostExec: host memory, the
// CPU's threads; render.backend = cpu-bvh), which runs in CI the very code the GPU runs, without
// a GPU. cpu_backend.h documents what a backend gives the frames.
//
// The world is copied into the policy's memory (Exec::Store) when the scene changed since the last
// copy (an animated scene: every frame), the previous frame's scene, BVH and lights too when the
// frame carries them, so that an animated scene's history is judged in its own frame's scene as on
// the CPU (GRIS, Lin et al. 2022, sec. 5).
#pragma once
#include <memory>
#include <utility>
#include <vector>

#include "backends/bvh.h"
#include "backends/bvh_traverse.h"
#include "backends/view_upload.h"
#include "frame/cpu_backend.h"
#include "frame/frame_world.h"
#include "frame/gbuffer.h"
#include "frame/pixel_sampler.h"
#include "scene/animation.h"

namespace rl {

namespace bvh_backend_detail {

// build_gbuffer's pixel (cpu_backend.h), its camera ray traced in the BVH.
struct PrimaryStage {
  PathWorld w;
  BvhView bvh;
  PerspectiveCamera camera;
  CameraSampling sampling;
  int frame, sample;
  const Mat4* back;
  uint32_t back_count;
  GPacked* pixels;
  Rgb* emitted;
  GMotion* motion;
  RESTIR_HD void operator()(int x, int y) const {
    const Ray ray = camera_ray(sampling, camera, x, y, frame, sample);
    Hit hit;
    const bool found = bvh_trace(bvh, ray, false, &hit);
    const size_t i = size_t(y) * size_t(camera.width()) + size_t(x);
    fill_gpacked(w.scene, w.lights, ray, found ? &hit : nullptr, pixels[i], emitted[i], back, back_count, motion ? motion + i : nullptr);
  }
};

// One ray of a queue traced in the BVH: its closest hit (hits) or whether anything blocks it (blocked).
struct TraceStage {
  BvhView bvh;
  const Ray* rays;
  Hit* hits;
  uint8_t* blocked;
  RESTIR_HD void operator()(size_t i) const {
    if (hits) {
      Hit h;
      bvh_trace(bvh, rays[i], false, &h);
      hits[i] = h;
    } else {
      blocked[i] = bvh_trace(bvh, rays[i], true, nullptr) ? 1 : 0;
    }
  }
};

}  // namespace bvh_backend_detail

template <class ExecT>
struct BvhBackend {
  using Exec = ExecT;
  using Tracer = BvhTracer;

  class World {
   public:
    void update(const RenderContext& ctx, const FrameInfo& frame) {
      if (!uploaded_ || ctx.accel.generation() != generation_) {
        StageTimer timer(frame.stages, "upload");
        store_.clear();
        generation_ = ctx.accel.generation();
        fw_.tracer = BvhTracer{store_bvh_view(store_, build_bvh(ctx.scene, ctx.options.render.bvh)), {}};
        fw_.world = PathWorld{store_scene_view(store_, ctx.accel.scene_view()), store_lights_view(store_, ctx.lights.view()),
                              ctx.accel.ray_epsilon()};
        fw_.animated = scene_animated(ctx.scene);
        uploaded_ = true;
      }
      update_previous(ctx, frame);
      if (!slots_.data) {
        slots_.reserve(kRaySlotWords);
        Exec::zero(slots_, kRaySlotWords);
      }
      const RayCounter counter{frame.stages ? slots_.data : nullptr};  // counting while stage times are recorded
      fw_.tracer.rays = counter, fw_.previous_tracer.rays = counter;
    }
    const FrameWorld<Tracer>& view() const { return fw_; }
    // The rays traced so far: the tracers' slots (in the policy's memory) and the queues' tally.
    RayCounts ray_totals() const {
      if (!slots_.data) return tally_.counts();
      uint64_t host[kRaySlotWords];
      Exec::download(host, slots_, kRaySlotWords);
      return sum_ray_slots(host) + tally_.counts();
    }
    RayTally& tally() const { return tally_; }

   private:
    // The previous frame's world and lights, and the motion between the frames (the frame's own).
    void update_previous(const RenderContext& ctx, const FrameInfo& frame) {
      fw_.has_previous = frame.previous_scene && frame.previous_accel;
      fw_.has_previous_lights = frame.previous_lights != nullptr;
      const std::vector<Mat4> back = motion_back(ctx.scene, frame.index);
      if (!fw_.has_previous && !fw_.has_previous_lights && back.empty()) return;
      StageTimer timer(frame.stages, "upload");
      previous_store_.clear();
      if (fw_.has_previous) {
        const Lights& lights = frame.previous_lights ? *frame.previous_lights : ctx.lights;
        fw_.previous_tracer = BvhTracer{store_bvh_view(previous_store_, build_bvh(*frame.previous_scene, ctx.options.render.bvh)), {}};
        fw_.previous_world = PathWorld{store_scene_view(previous_store_, frame.previous_accel->scene_view()),
                                       store_lights_view(previous_store_, lights.view()), frame.previous_accel->ray_epsilon()};
      }
      if (fw_.has_previous_lights) fw_.previous_lights = store_lights_view(previous_store_, frame.previous_lights->view());
      fw_.back = previous_store_.upload(back);
      fw_.forward = previous_store_.upload(motion_forward(back));
      fw_.animation_count = uint32_t(back.size());
    }

    typename Exec::Store store_, previous_store_;
    typename Exec::template Array<uint64_t> slots_;
    mutable RayTally tally_;
    FrameWorld<Tracer> fw_;
    uint64_t generation_ = 0;
    bool uploaded_ = false;
  };

  static void primary_hits(const World& w, const RenderContext& ctx, const FrameInfo& frame, int sample, GPacked* pixels,
                           Rgb* emitted, GMotion* motion) {
    const FrameWorld<Tracer>& fw = w.view();
    const PerspectiveCamera& camera = *frame.camera;
    const bvh_backend_detail::PrimaryStage stage{fw.world,   fw.tracer.bvh,      camera, camera_sampling(ctx.options), frame.index, sample,
                                                 fw.back,    fw.animation_count, pixels, emitted, motion};
    Exec::for_pixels(camera.width(), camera.height(), stage, "primary hits");
    w.tally().add(uint64_t(camera.width()) * uint64_t(camera.height()), false);  // a camera ray a pixel
  }
  static void trace_closest(const World& w, const Ray* rays, Hit* hits, size_t n, bool) {
    Exec::for_each(n, bvh_backend_detail::TraceStage{w.view().tracer.bvh, rays, hits, nullptr}, "closest hits");
    w.tally().add(n, false);
  }
  static void trace_any(const World& w, const Ray* rays, uint8_t* blocked, size_t n) {
    Exec::for_each(n, bvh_backend_detail::TraceStage{w.view().tracer.bvh, rays, nullptr, blocked}, "shadow rays");
    w.tally().add(n, true);
  }
};

// The host twin of the CUDA backend (render.backend = cpu-bvh).
using HostBvhBackend = BvhBackend<HostExec>;

// An algorithm's frame on the host backend render.backend names (cpu or cpu-bvh): what its registry
// row's `make` returns (registry.cpp). The CUDA instantiation lives in its <algo>.cu.
template <template <class> class Frame, class... Args>
std::unique_ptr<Integrator> make_on_host(const RenderContext& ctx, Args&&... args) {
  if (ctx.options.render.backend == Backend::cpu_bvh) return std::make_unique<Frame<HostBvhBackend>>(ctx, std::forward<Args>(args)...);
  return std::make_unique<Frame<CpuBackend>>(ctx, std::forward<Args>(args)...);
}

}  // namespace rl
