// ReSTIR DI's frame as a sequence of per-pixel stages over flat buffers, written once for any
// execution policy (host_exec.h): the CUDA backend runs it with cuda::CudaExec (restir_di_cuda.cu),
// and its host twin with HostExec over the same BVH traversal (restir_di_twin.cpp), so that CI
// proves the driver -- buffers, stage order, random streams, history -- without a GPU.
// The stages are those of the CPU's restir_di.cpp, in its order, with its random streams: primary
// hits, light tiles (drawn on the host, copied), initial candidates, temporal reuse, the spatial
// rounds, shading; each pixel's work is di_pixel.h's and reuse_pixel.h's, the code the CPU runs.
// Static scenes only so far: an animated scene's history needs the previous frame's lights and
// BVH on the device (the CPU's DiBridge).
#pragma once
#include <memory>
#include <vector>

#include "backends/bvh.h"
#include "backends/bvh_traverse.h"
#include "backends/view_upload.h"
#include "integrators/di_pixel.h"
#include "integrators/di_sampling.h"
#include "integrators/path_tracer.h"
#include "integrators/reuse_pixel.h"

namespace rl {

namespace di_frame_detail {

// The reuse bridges of one frame (DiViewBridge over the BVH), made per pixel by the reuse stages.
struct Bridges {
  PathWorld world;
  BvhTracer tracer;
  bool canonical_visibility, other_visibility;
  RESTIR_HD DiViewBridge<BvhTracer> operator()(const GSurface* const* surfaces, int, bool temporal) const {
    return {&world, &tracer, surfaces, canonical_visibility, other_visibility, temporal, true};
  }
};

// One chain's pre-sampled light tiles in the policy's memory (LightTiles' arrays).
struct Tiles {
  const LightTileEntry* lights = nullptr;
  const EnvTileEntry* env = nullptr;
  int count = 0, size = 0, env_size = 0;
  RESTIR_HD DiTileView of(int x, int y, int width, const ReuseFrame& f) const {
    DiTileView v;
    if (count <= 0 || size <= 0) return v;  // LightTiles::tile_of's empty span
    const size_t t = light_tile_index(x, y, width, f.frame, f.seed, f.chain, count);
    v.lights = lights + t * size_t(size), v.light_count = uint32_t(size);
    if (env_size > 0) v.env = env + t * size_t(env_size), v.env_count = uint32_t(env_size);
    return v;
  }
};

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

struct CandidateStage {
  PathWorld w;
  BvhTracer tracer;
  DiOptions di;
  ReuseFrame f;
  GBufferView g;
  Tiles tiles;
  DiReservoir* out;
  RESTIR_HD void operator()(int x, int y) const {
    const uint32_t p = uint32_t(y * g.width + x);
    Pcg32 rng = make_rng(p, f.frame, RngPass::light_candidates, f.seed, f.chain);
    out[p] = di_initial_reservoir_in(w, tracer, g.at(x, y), di.light_candidates, di.bsdf_candidates, di.visibility_reuse, rng,
                                     tiles.of(x, y, g.width, f));
  }
};

struct TemporalStage {
  Bridges bridges;
  ReuseOptions rp;
  GBufferView g, previous_g;
  PerspectiveCamera previous_camera;
  const DiReservoir *reservoirs, *history;
  DiReservoir* next;
  ReuseFrame f;
  ReuseDebugView dbg;
  RESTIR_HD void operator()(int x, int y) const {
    temporal_pixel(rp, g, previous_g, previous_camera, reservoirs, history, next, bridges, f, dbg, x, y);
  }
};

struct SpatialStage {
  Bridges bridges;
  ReuseOptions rp;
  GBufferView g;
  const DiReservoir* reservoirs;
  DiReservoir* next;
  ReuseFrame f;
  int round;
  ReuseDebugView dbg;
  RESTIR_HD void operator()(int x, int y) const { spatial_pixel(rp, g, reservoirs, next, bridges, f, round, dbg, x, y); }
};

struct ShadeStage {
  PathWorld w;
  BvhTracer tracer;
  GBufferView g;
  const DiReservoir* reservoirs;
  bool visibility_reuse;
  DebugView view;
  ReuseDebugView dbg;
  ReuseFrame f;
  Rgb* sum;
  RESTIR_HD void operator()(int x, int y) const {
    const uint32_t p = uint32_t(y * g.width + x);
    Rgb d;
    if (debug_view_value(view, reservoirs[p], dbg, p, d)) {
      sum[p] += d;
      return;
    }
    sum[p] += di_shade(w, tracer, g.at(x, y), reservoirs[p], visibility_reuse, p, f.frame, f.seed, f.chain);
  }
};

// render_chains' average: a division, as the CPU's, for the same rounding.
struct AverageStage {
  Rgb* sum;
  float spp;
  RESTIR_HD void operator()(size_t i) const { sum[i] = sum[i] / spp; }
};

}  // namespace di_frame_detail

template <class Exec>
class DiFrameRenderer final : public Integrator {
 public:
  explicit DiFrameRenderer(const RenderContext& ctx) : ctx_(ctx) { upload_world(); }

  void render_frame(const FrameInfo& frame, Image& out) override {
    if (ctx_.accel.generation() != uploaded_generation_) {  // frame 0 again after FrameRenderer::reset
      StageTimer timer(frame.stages, "upload");
      upload_world();
    }
    const int spp = ctx_.options.render.spp;
    if (int(chains_.size()) != spp) {
      chains_.clear();
      for (int s = 0; s < spp; ++s) chains_.push_back(std::make_unique<Chain>());
    }
    const size_t pixels = out.size();
    sum_.reserve(pixels);
    Exec::zero(sum_, pixels);
    for (int s = 0; s < spp; ++s) render_chain(frame, s, *chains_[size_t(s)]);
    Exec::for_each(pixels, di_frame_detail::AverageStage{sum_.data, float(spp)}, "averaging the chains");
    Exec::download(out.pixels.data(), sum_, pixels);
  }

 private:
  template <class T>
  using Array = typename Exec::template Array<T>;

  // One chain (pixel sample) of reservoirs: ReservoirChain's buffers in the policy's memory.
  struct Chain {
    Array<GSurface> gbuffer, previous_gbuffer;
    Array<DiReservoir> reservoirs, previous, scratch;
    Array<uint8_t> source;
    Array<uint16_t> tried, rejected;
    Array<LightTileEntry> tiles;
    Array<EnvTileEntry> env_tiles;
    int previous_width = 0, previous_height = 0;
    bool has_history = false;
    ReuseDebugView debug() { return {source.data, tried.data, rejected.data}; }
  };

  void render_chain(const FrameInfo& frame, int s, Chain& c) {
    using namespace di_frame_detail;
    const Options& o = ctx_.options;
    const DiOptions& di = o.di;
    const ReuseOptions& rp = di.reuse;
    const PerspectiveCamera& camera = *frame.camera;
    const int w = camera.width(), h = camera.height();
    const ReuseFrame f{uint32_t(frame.index), o.render.seed, uint32_t(s)};
    const BvhTracer tracer{bvh_};
    begin_frame(frame, s, c);
    const GBufferView g{c.gbuffer.data, w, h};
    upload_tiles(frame, f, c);
    {
      StageTimer timer(frame.stages, "candidates");
      const Tiles tiles{c.tiles.data, c.env_tiles.data, tiles_.count(), tiles_.size(), tiles_.env_size()};
      Exec::for_pixels(w, h, CandidateStage{world_, tracer, di, f, g, tiles, c.reservoirs.data}, "ReSTIR DI candidates");
    }
    const Bridges bridges{world_, tracer, di.visibility_reuse, di.visibility_reuse && di.neighbor_visibility};
    if (rp.temporal && c.has_history && c.previous_width == w && c.previous_height == h) {
      StageTimer timer(frame.stages, "temporal");
      const PerspectiveCamera& previous_camera = frame.previous_camera ? *frame.previous_camera : camera;
      const TemporalStage stage{bridges, rp, g, GBufferView{c.previous_gbuffer.data, w, h}, previous_camera, c.reservoirs.data,
                                c.previous.data, c.scratch.data, f, c.debug()};
      Exec::for_pixels(w, h, stage, "ReSTIR DI temporal reuse");
      c.reservoirs.swap(c.scratch);
    }
    {
      StageTimer timer(frame.stages, "spatial");
      for (int round = 0; rp.spatial_neighbors > 0 && round < rp.spatial_rounds; ++round) {
        Exec::for_pixels(w, h, SpatialStage{bridges, rp, g, c.reservoirs.data, c.scratch.data, f, round, c.debug()},
                         "ReSTIR DI spatial reuse");
        c.reservoirs.swap(c.scratch);
      }
    }
    {
      StageTimer timer(frame.stages, "shading");
      const ShadeStage stage{world_, tracer, g, c.reservoirs.data, di.visibility_reuse, o.render.debug_view, c.debug(), f, sum_.data};
      Exec::for_pixels(w, h, stage, "ReSTIR DI shading");
    }
    // ReservoirChain::end_frame: this frame's reservoirs and surfaces are the next frame's history.
    c.previous.swap(c.reservoirs);
    c.previous_gbuffer.swap(c.gbuffer);
    c.previous_width = w, c.previous_height = h;
    c.has_history = true;
  }

  // Primary hits of chain s, buffers sized for the frame, debug counters cleared.
  void begin_frame(const FrameInfo& frame, int s, Chain& c) {
    StageTimer timer(frame.stages, "primary");
    const PerspectiveCamera& camera = *frame.camera;
    const size_t n = size_t(camera.width()) * size_t(camera.height());
    c.gbuffer.reserve(n), c.previous_gbuffer.reserve(n);
    c.reservoirs.reserve(n), c.previous.reserve(n), c.scratch.reserve(n);
    c.source.reserve(n), c.tried.reserve(n), c.rejected.reserve(n);
    Exec::zero(c.source, n), Exec::zero(c.tried, n), Exec::zero(c.rejected, n);
    const di_frame_detail::PrimaryStage stage{world_, bvh_, camera, camera_sampling(ctx_.options), frame.index, s, c.gbuffer.data};
    Exec::for_pixels(camera.width(), camera.height(), stage, "ReSTIR DI primary hits");
  }

  // This frame's light tiles for chain f.chain, drawn on the host (LightTiles::build, the CPU's
  // streams) and copied: count x size entries, a few hundred kilobytes.
  void upload_tiles(const FrameInfo& frame, const ReuseFrame& f, Chain& c) {
    const DiOptions& di = ctx_.options.di;
    StageTimer timer(frame.stages, "light_tiles");
    if (di.light_tiles > 0 && di.light_candidates > 0)
      tiles_.build(ctx_.lights, di.light_tiles, di.light_tile_size, f.frame, f.seed, f.chain, di.env_tile_size);
    else
      tiles_.build(ctx_.lights, 0, 0, f.frame, f.seed, f.chain);
    Exec::upload(c.tiles, tiles_.entries().data(), tiles_.entries().size());
    Exec::upload(c.env_tiles, tiles_.env_entries().data(), tiles_.env_entries().size());
  }

  // The scene, lights and BVH as they are now, in the policy's memory.
  void upload_world() {
    store_.clear();
    uploaded_generation_ = ctx_.accel.generation();
    bvh_ = store_bvh_view(store_, build_bvh(ctx_.scene));
    world_.scene = store_scene_view(store_, ctx_.accel.scene_view());
    world_.lights = store_lights_view(store_, ctx_.lights.view());
    world_.ray_epsilon = ctx_.accel.ray_epsilon();
  }

  RenderContext ctx_;
  uint64_t uploaded_generation_ = 0;
  typename Exec::Store store_;
  BvhView bvh_;
  PathWorld world_;
  LightTiles tiles_;  // the host's copy of the current chain's tiles
  std::vector<std::unique_ptr<Chain>> chains_;
  Array<Rgb> sum_;
};

}  // namespace rl
