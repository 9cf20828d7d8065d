// ReSTIR DI's frame as a sequence of per-pixel stages over flat buffers, written once for any
// execution policy (host_exec.h): the CUDA backend runs it with cuda::CudaExec (restir_di_cuda.cu),
// and its host twin with HostExec over the same BVH traversal (frame_twins.cpp), so that CI proves
// the driver -- buffers, stage order, random streams, tiles, history -- without a GPU.
// The stages are those of the CPU's restir_di.cpp, in its order, with its random streams: primary
// hits, light tiles (drawn on the host, copied), initial candidates, temporal reuse, the spatial
// rounds, shading; each pixel's work is di_pixel.h's and reuse_pixel.h's, the code the CPU runs.
#pragma once
#include "integrators/restir_di/restir_di_pixel.h"
#include "integrators/restir_di/di_sampling.h"
#include "frame/reuse_frame.h"

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
    if (add_debug_view(view, reservoirs[p], dbg, p, sum)) return;
    sum[p] += di_shade(w, tracer, g.at(x, y), reservoirs[p], visibility_reuse, p, f.frame, f.seed, f.chain);
  }
};

}  // namespace di_frame_detail

template <class Exec>
class DiFrameRenderer final : public Integrator {
 public:
  explicit DiFrameRenderer(const RenderContext& ctx) : ctx_(ctx) { check_frame_supported(ctx, "restir-di"); }

  void render_frame(const FrameInfo& frame, Image& out) override {
    world_.update(ctx_, frame);
    render_exec_chains<Exec>(chains_, ctx_.options.render.spp, sum_, out, [&](int s, Chain& c) { render_chain(frame, s, c); });
  }

 private:
  struct Chain : ExecChain<Exec, DiReservoir> {
    typename Exec::template Array<LightTileEntry> tiles;
    typename Exec::template Array<EnvTileEntry> env_tiles;
  };

  void render_chain(const FrameInfo& frame, int s, Chain& c) {
    using namespace di_frame_detail;
    const Options& o = ctx_.options;
    const DiOptions& di = o.di;
    const ReuseFrame f{uint32_t(frame.index), o.render.seed, uint32_t(s)};
    const BvhTracer tracer{world_.bvh};
    c.begin_frame(world_, o, frame, s);
    upload_tiles(frame, f, c);
    {
      StageTimer timer(frame.stages, "candidates");
      const Tiles tiles{c.tiles.data, c.env_tiles.data, tiles_.count(), tiles_.size(), tiles_.env_size()};
      Exec::for_pixels(c.width, c.height, CandidateStage{world_.world, tracer, di, f, c.view(), tiles, c.reservoirs.data},
                       "ReSTIR DI candidates");
    }
    c.reuse(di.reuse, frame, Bridges{world_.world, tracer, di.visibility_reuse, di.visibility_reuse && di.neighbor_visibility}, f);
    {
      StageTimer timer(frame.stages, "shading");
      const ShadeStage stage{world_.world,        tracer,    c.view(), c.reservoirs.data, di.visibility_reuse,
                             o.render.debug_view, c.debug(), f,        sum_.data};
      Exec::for_pixels(c.width, c.height, stage, "ReSTIR DI shading");
    }
    c.end_frame();
  }

  // This frame's light tiles for chain f.chain, drawn on the host (LightTiles::build, the CPU's
  // streams) and copied: count x size entries (1 MB at the defaults, plus 3.6 MB of environment
  // directions where there is an environment). Drawing them on the device is left to do.
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

  RenderContext ctx_;
  ExecWorld<Exec> world_;
  LightTiles tiles_;  // the host's copy of the current chain's tiles
  std::vector<std::unique_ptr<Chain>> chains_;
  typename Exec::template Array<Rgb> sum_;
};

}  // namespace rl
