// ReSTIR GI's frame as a sequence of per-pixel stages over flat buffers, written once for any
// execution policy (host_exec.h), as di_frame.h is for ReSTIR DI: the CUDA backend runs it with
// cuda::CudaExec (restir_gi_cuda.cu), its host twin with HostExec (frame_twins.cpp).
// The stages are those of the CPU's restir_gi.cpp, in its order, with its random streams: primary
// hits, the initial sample and direct light, temporal reuse, the spatial rounds, shading; each
// pixel's work is gi_pixel.h's and reuse_pixel.h's, the code the CPU runs.
#pragma once
#include "integrators/restir_gi/restir_gi_pixel.h"
#include "frame/reuse_frame.h"

namespace rl {

namespace gi_frame_detail {

// The reuse bridges of one frame (GiViewBridge over the BVH), made per pixel by the reuse stages.
struct Bridges {
  PathWorld world;
  BvhTracer tracer;
  GiTarget kind;
  RESTIR_HD GiViewBridge<BvhTracer> operator()(const GSurface* const* surfaces, int, bool) const {
    return {&world, &tracer, kind, surfaces};
  }
};

struct CandidateStage {
  PathWorld w;
  BvhTracer tracer;
  PathOptions path;  // the secondary path's: path.max_depth - 1 bounces
  GiTarget kind;
  ReuseFrame f;
  GBufferView g;
  GiReservoir* out;
  Rgb* specular;
  RESTIR_HD void operator()(int x, int y) const {
    const uint32_t p = uint32_t(y * g.width + x);
    Pcg32 rng = make_rng(p, f.frame, RngPass::path, f.seed, f.chain);
    Rgb spec(0);
    out[p] = gi_initial_in(w, tracer, path, kind, g.at(x, y), rng, spec);
    specular[p] = spec + gi_direct_in(w, tracer, g.at(x, y), rng);
  }
};

struct ShadeStage {
  GBufferView g;
  const GiReservoir* reservoirs;
  const Rgb* specular;
  DebugView view;
  ReuseDebugView dbg;
  Rgb* sum;
  RESTIR_HD void operator()(int x, int y) const {
    const uint32_t p = uint32_t(y * g.width + x);
    if (add_debug_view(view, reservoirs[p], dbg, p, sum)) return;
    sum[p] += gi_shade(g.at(x, y), reservoirs[p], specular[p]);
  }
};

}  // namespace gi_frame_detail

template <class Exec>
class GiFrameRenderer final : public Integrator {
 public:
  explicit GiFrameRenderer(const RenderContext& ctx) : ctx_(ctx), path_(ctx.options.path) {
    check_frame_supported(ctx, "restir-gi");
    path_.max_depth = ctx.options.path.max_depth - 1;  // the sample point's radiance: one bounce less
  }

  void render_frame(const FrameInfo& frame, Image& out) override {
    world_.update(ctx_, frame);
    render_exec_chains<Exec>(chains_, ctx_.options.render.spp, sum_, out, [&](int s, Chain& c) { render_chain(frame, s, c); });
  }

 private:
  struct Chain : ExecChain<Exec, GiReservoir> {
    typename Exec::template Array<Rgb> specular;  // not resampled: direct light, or a plain path through a delta BSDF
  };

  void render_chain(const FrameInfo& frame, int s, Chain& c) {
    using namespace gi_frame_detail;
    const Options& o = ctx_.options;
    const ReuseFrame f{uint32_t(frame.index), o.render.seed, uint32_t(s)};
    const BvhTracer tracer{world_.bvh};
    c.begin_frame(world_, o, frame, s);
    c.specular.reserve(size_t(c.width) * size_t(c.height));
    {
      StageTimer timer(frame.stages, "candidates");
      const CandidateStage stage{world_.world, tracer, path_, o.gi.target, f, c.view(), c.reservoirs.data, c.specular.data};
      Exec::for_pixels(c.width, c.height, stage, "ReSTIR GI samples");
    }
    c.reuse(o.gi.reuse, frame, Bridges{world_.world, tracer, o.gi.target}, f);
    {
      StageTimer timer(frame.stages, "shading");
      const ShadeStage stage{c.view(), c.reservoirs.data, c.specular.data, o.render.debug_view, c.debug(), sum_.data};
      Exec::for_pixels(c.width, c.height, stage, "ReSTIR GI shading");
    }
    c.end_frame();
  }

  RenderContext ctx_;
  PathOptions path_;
  ExecWorld<Exec> world_;
  std::vector<std::unique_ptr<Chain>> chains_;
  typename Exec::template Array<Rgb> sum_;
};

}  // namespace rl
