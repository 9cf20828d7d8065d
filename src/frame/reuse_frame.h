// The parts of a ReSTIR frame that every integrator's GPU driver shares (di_frame.h, pt_frame.h),
// written once for any execution policy (host_exec.h): the scene in the policy's memory, one chain
// of reservoirs with its G-buffers and debug counters, and the stages around the integrator's own
// -- primary hits, temporal reuse, the spatial rounds, the chains' average -- in the CPU's order
// (reuse_passes.h: ReservoirChain) with its random streams. Static scenes only so far: an animated
// scene's history needs the previous frame's lights and BVH in the policy's memory.
#pragma once
#include <memory>
#include <vector>

#include "backends/bvh.h"
#include "backends/bvh_traverse.h"
#include "backends/view_upload.h"
#include "frame/integrator.h"
#include "integrators/path/path_pixel.h"
#include "frame/reuse_pixel.h"

namespace rl {

// Throws std::runtime_error when the frame drivers cannot render this context yet: an animated
// scene, planted biases (a CPU test harness). `integrator` names it in the message.
void check_frame_supported(const RenderContext& ctx, const char* integrator);

namespace frame_detail {

// build_gbuffer's pixel, traced in the BVH. A static scene: no motion (its maps are empty there too).
struct PrimaryStage {
  PathWorld w;
  BvhView bvh;
  PerspectiveCamera camera;
  CameraSampling sampling;
  int frame, sample;
  GSurface* g;
  RESTIR_HD void operator()(int x, int y) const {
    const Ray ray = camera_ray(sampling, camera, x, y, frame, sample);
    Hit hit;
    const bool found = bvh_trace(bvh, ray, false, &hit);
    fill_gsurface(w.scene, w.lights, ray, found ? &hit : nullptr, g[size_t(y) * size_t(camera.width()) + size_t(x)], nullptr, 0);
  }
};

template <class Res, class Bridges>
struct TemporalStage {
  Bridges bridges;
  ReuseOptions rp;
  GBufferView g, previous_g;
  PerspectiveCamera previous_camera;
  const Res *reservoirs, *history;
  Res* next;
  ReuseFrame f;
  ReuseDebugView dbg;
  RESTIR_HD void operator()(int x, int y) const {
    temporal_pixel(rp, g, previous_g, previous_camera, reservoirs, history, next, bridges, f, dbg, x, y);
  }
};

template <class Res, class Bridges>
struct SpatialStage {
  Bridges bridges;
  ReuseOptions rp;
  GBufferView g;
  const Res* reservoirs;
  Res* next;
  ReuseFrame f;
  int round;
  ReuseDebugView dbg;
  RESTIR_HD void operator()(int x, int y) const { spatial_pixel(rp, g, reservoirs, next, bridges, f, round, dbg, x, y); }
};

// render_chains' average: a division, as the CPU's, for the same rounding.
struct AverageStage {
  Rgb* sum;
  float spp;
  RESTIR_HD void operator()(size_t i) const { sum[i] = sum[i] / spp; }
};

}  // namespace frame_detail

// The scene, its lights and its BVH in the policy's memory.
template <class Exec>
struct ExecWorld {
  typename Exec::Store store;
  BvhView bvh;
  PathWorld world;
  bool uploaded = false;
  uint64_t generation = 0;
  // Copies them (again) when the scene's BVH changed since (FrameRenderer::reset): frame 0 again.
  void update(const RenderContext& ctx, const FrameInfo& frame) {
    if (uploaded && ctx.accel.generation() == generation) return;
    StageTimer timer(frame.stages, "upload");
    store.clear();
    generation = ctx.accel.generation();
    bvh = store_bvh_view(store, build_bvh(ctx.scene));
    world.scene = store_scene_view(store, ctx.accel.scene_view());
    world.lights = store_lights_view(store, ctx.lights.view());
    world.ray_epsilon = ctx.accel.ray_epsilon();
    uploaded = true;
  }
};

// One chain (pixel sample) of reservoirs in the policy's memory: ReservoirChain's buffers and steps.
template <class Exec, class Res>
struct ExecChain {
  template <class T>
  using Array = typename Exec::template Array<T>;
  Array<GSurface> gbuffer, previous_gbuffer;
  Array<Res> reservoirs, previous, scratch;
  Array<uint8_t> source;
  Array<uint16_t> tried, rejected;
  int width = 0, height = 0, previous_width = 0, previous_height = 0;
  bool has_history = false;

  ReuseDebugView debug() { return {source.data, tried.data, rejected.data}; }
  GBufferView view() const { return {gbuffer.data, width, height}; }

  // Primary hits of chain s, buffers sized for the frame, debug counters cleared.
  void begin_frame(const ExecWorld<Exec>& w, const Options& o, const FrameInfo& frame, int s) {
    StageTimer timer(frame.stages, "primary");
    const PerspectiveCamera& camera = *frame.camera;
    width = camera.width(), height = camera.height();
    const size_t n = size_t(width) * size_t(height);
    gbuffer.reserve(n), previous_gbuffer.reserve(n);
    reservoirs.reserve(n), previous.reserve(n), scratch.reserve(n);
    source.reserve(n), tried.reserve(n), rejected.reserve(n);
    Exec::zero(source, n), Exec::zero(tried, n), Exec::zero(rejected, n);
    const frame_detail::PrimaryStage stage{w.world, w.bvh, camera, camera_sampling(o), frame.index, s, gbuffer.data};
    Exec::for_pixels(width, height, stage, "primary hits");
  }

  // Temporal reuse (when there is a compatible history), then the spatial rounds; bridges(surfaces,
  // n, temporal) makes a pixel's bridge (mis.h).
  template <class Bridges>
  void reuse(const ReuseOptions& rp, const FrameInfo& frame, const Bridges& bridges, const ReuseFrame& f) {
    using namespace frame_detail;
    if (rp.temporal && has_history && previous_width == width && previous_height == height) {
      StageTimer timer(frame.stages, "temporal");
      const PerspectiveCamera& previous_camera = frame.previous_camera ? *frame.previous_camera : *frame.camera;
      const TemporalStage<Res, Bridges> stage{bridges,         rp,
                                              view(),          GBufferView{previous_gbuffer.data, width, height},
                                              previous_camera, reservoirs.data,
                                              previous.data,   scratch.data,
                                              f,               debug()};
      Exec::for_pixels(width, height, stage, "temporal reuse");
      reservoirs.swap(scratch);
    }
    StageTimer timer(frame.stages, "spatial");
    for (int round = 0; rp.spatial_neighbors > 0 && round < rp.spatial_rounds; ++round) {
      const SpatialStage<Res, Bridges> stage{bridges, rp, view(), reservoirs.data, scratch.data, f, round, debug()};
      Exec::for_pixels(width, height, stage, "spatial reuse");
      reservoirs.swap(scratch);
    }
  }

  // This frame's reservoirs and surfaces are the next frame's history.
  void end_frame() {
    previous.swap(reservoirs);
    previous_gbuffer.swap(gbuffer);
    previous_width = width, previous_height = height;
    has_history = true;
  }
};

// render_chains for a policy: `spp` chains (made on first use) rendered in order by
// render_chain(s, chain, sum), each adding its radiance to sum, then averaged into `out`.
template <class Exec, class Chain, class RenderChain>
void render_exec_chains(std::vector<std::unique_ptr<Chain>>& chains, int spp, typename Exec::template Array<Rgb>& sum, Image& out,
                        const RenderChain& render_chain) {
  if (int(chains.size()) != spp) {
    chains.clear();
    for (int s = 0; s < spp; ++s) chains.push_back(std::make_unique<Chain>());
  }
  const size_t pixels = out.size();
  sum.reserve(pixels);
  Exec::zero(sum, pixels);
  for (int s = 0; s < spp; ++s) render_chain(s, *chains[size_t(s)]);
  Exec::for_each(pixels, frame_detail::AverageStage{sum.data, float(spp)}, "averaging the chains");
  Exec::download(out.pixels.data(), sum, pixels);
}

}  // namespace rl
