// ReSTIR PT's frame as a sequence of per-pixel stages over flat buffers, written once for any
// execution policy (host_exec.h), as di_frame.h is for ReSTIR DI: the CUDA backend runs it with
// cuda::CudaExec (restir_pt_cuda.cu), its host twin with HostExec (frame_twins.cpp).
// The stages are those of the CPU's restir_pt.cpp, in its order, with its random streams: primary
// hits, initial paths, temporal reuse, the spatial rounds, shading; with pt.direct = restir-di,
// di_frame.h's ReSTIR DI on the same policy adds the emission seen and the direct light. Each
// pixel's work is pt_path_kernel.h's and reuse_pixel.h's, the code the CPU runs.
#pragma once
#include <string>
#include <vector>

#include "integrators/restir_pt/restir_pt_pixel.h"
#include "frame/reuse_frame.h"

namespace rl {

namespace pt_frame_detail {

// The reuse bridges of one frame (PtViewBridge over the BVH), made per pixel by the reuse stages.
struct Bridges {
  PathWorld world;
  BvhTracer tracer;
  PathSettings ps;
  RESTIR_HD PtViewBridge<BvhTracer> operator()(const GSurface* const* surfaces, int, bool) const {
    return {&world, &tracer, &ps, surfaces};
  }
};

struct CandidateStage {
  PathWorld w;
  BvhTracer tracer;
  PathSettings ps;
  int candidates;
  ReuseFrame f;
  GBufferView g;
  PathReservoir* out;
  RESTIR_HD void operator()(int x, int y) const {
    const uint32_t p = uint32_t(y * g.width + x);
    const uint64_t path_seed = initial_paths_seed(f.seed, p, f.frame, f.chain);
    out[p] = initial_path_reservoir_in(w, tracer, ps, g.at(x, y), path_seed, candidates);
  }
};

// Emission at the primary hit (unless ReSTIR DI adds it) + f(Y) W, or a debug view.
struct ShadeStage {
  GBufferView g;
  const PathReservoir* reservoirs;
  bool direct_from_di;
  DebugView view;
  ReuseDebugView dbg;
  Rgb* sum;
  RESTIR_HD void operator()(int x, int y) const {
    const uint32_t p = uint32_t(y * g.width + x);
    const PathReservoir& r = reservoirs[p];
    if (add_debug_view(view, r, dbg, p, sum, r.has_sample() ? r.sample.rc : 0)) return;
    sum[p] += pt_shade(g.at(x, y), r, direct_from_di);
  }
};

}  // namespace pt_frame_detail

template <class Exec>
class PtFrameRenderer final : public Integrator {
 public:
  // make_direct: ReSTIR DI on the same policy (make_cuda_restir_di, make_host_twin_restir_di),
  // called when pt.direct = restir-di.
  PtFrameRenderer(const RenderContext& ctx, std::unique_ptr<Integrator> (*make_direct)(const RenderContext&))
      : ctx_(ctx), settings_(path_settings(ctx.options)) {
    check_frame_supported(ctx, "restir-pt");
    if (ctx.options.pt.direct == DirectLighting::restir_di) direct_ = make_direct(ctx);
  }

  void render_frame(const FrameInfo& frame, Image& out) override {
    world_.update(ctx_, frame);
    render_exec_chains<Exec>(chains_, ctx_.options.render.spp, sum_, out, [&](int s, Chain& c) { render_chain(frame, s, c); });
    // pt.direct = restir-di: ReSTIR DI renders the emission seen and the direct light (same primary
    // rays), the paths only the indirect part (length >= 3).
    if (direct_ && ctx_.options.render.debug_view == DebugView::none) add_direct_light(*direct_, frame, out);
  }

 private:
  using Chain = ExecChain<Exec, PathReservoir>;

  void render_chain(const FrameInfo& frame, int s, Chain& c) {
    using namespace pt_frame_detail;
    const Options& o = ctx_.options;
    const ReuseFrame f{uint32_t(frame.index), o.render.seed, uint32_t(s)};
    const BvhTracer tracer{world_.bvh};
    c.begin_frame(world_, o, frame, s);
    {
      StageTimer timer(frame.stages, "candidates");
      Exec::for_pixels(c.width, c.height, CandidateStage{world_.world, tracer, settings_, o.pt.candidates, f, c.view(), c.reservoirs.data},
                       "ReSTIR PT initial paths");
    }
    c.reuse(o.pt.reuse, frame, Bridges{world_.world, tracer, settings_}, f);
    {
      StageTimer timer(frame.stages, "shading");
      const ShadeStage stage{c.view(), c.reservoirs.data, direct_ != nullptr, o.render.debug_view, c.debug(), sum_.data};
      Exec::for_pixels(c.width, c.height, stage, "ReSTIR PT shading");
    }
    if (o.render.debug_view == DebugView::reconnection_depth) {
      std::vector<PathReservoir> host(size_t(c.width) * size_t(c.height));
      Exec::download(host.data(), c.reservoirs, host.size());
      print_reconnection_histogram(frame.index, s, host);
    }
    c.end_frame();
  }

  RenderContext ctx_;
  PathSettings settings_;
  ExecWorld<Exec> world_;
  std::vector<std::unique_ptr<Chain>> chains_;
  typename Exec::template Array<Rgb> sum_;
  std::unique_ptr<Integrator> direct_;  // ReSTIR DI on the same policy when pt.direct = restir-di
};

}  // namespace rl
