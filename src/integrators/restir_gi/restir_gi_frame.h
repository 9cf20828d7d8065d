// ReSTIR GI (Ouyang et al. 2021, "ReSTIR GI: Path resampling for real-time path tracing"), one
// frame written once for every backend (cpu_backend.h): per pixel sample, primary hits, the
// initial sample and direct light, temporal reuse, the spatial rounds, shading.
//
// A sample is a secondary hit x_s with its normal and the radiance it reflects toward the visible
// point that traced it (its own emission is direct light, estimated at the visible point by one
// light sample, as the paper leaves direct lighting to ReSTIR DI / NEE); reuse reconnects another
// pixel's visible point to x_s (reconnection shift, jacobian eq. 11) and keeps the cached radiance.
// That cache assumes x_s reflects the same radiance toward every visible point (Lambertian x_s):
// exact for diffuse sample points, biased otherwise -- ReSTIR PT's reconnection evaluates x_s's
// BSDF instead. Reference: pt with the same path.* options.
//
// Temporal reuse in an animated scene: the cached radiance belongs to the previous frame's scene (a
// light switched off would leave a ghost), so the sample keeps the random stream of the path that
// estimated it, and the surface x_s lies on; GiBridge (restir_gi_pixel.h) replays it across the
// frames, each frame's target in its own scene, as GRIS requires; the Lambertian assumption stays.
#pragma once
#include <memory>
#include <vector>

#include "frame/reservoir_chain.h"
#include "integrators/restir_gi/restir_gi_pixel.h"

namespace rl {

namespace gi_frame_detail {

template <class Tracer>
struct CandidateStage {
  FrameWorld<Tracer> fw;
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
    out[p] = gi_initial(fw.world, fw.tracer, path, kind, g.at(x, y), rng, spec);
    specular[p] = spec + gi_direct(fw.world, fw.tracer, g.at(x, y), rng);
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

template <class B>
class RestirGiFrame final : public Integrator {
 public:
  using Exec = typename B::Exec;
  explicit RestirGiFrame(const RenderContext& ctx) : ctx_(ctx), path_(ctx.options.path) {
    path_.max_depth = ctx.options.path.max_depth - 1;  // the sample point's radiance: one bounce less
  }

  // The previous frame's scene and BVH for temporal reuse in an animated scene (GiBridge).
  bool needs_previous_scene() const override { return scene_animated(ctx_.scene) && ctx_.options.gi.reuse.temporal; }

  void render_frame(const FrameInfo& frame, Image& out) override {
    world_.update(ctx_, frame);
    render_chains<Exec>(chains_, ctx_.options.render.spp, sum_, out, [&](int s, Chain& c) { render_chain(frame, s, c); });
  }

 private:
  struct Chain : ReservoirChain<B, GiReservoir> {
    typename Exec::template Array<Rgb> specular;  // not resampled: direct light, or a plain path through a delta BSDF
  };

  void render_chain(const FrameInfo& frame, int s, Chain& c) {
    using namespace gi_frame_detail;
    using Tracer = typename B::Tracer;
    const Options& o = ctx_.options;
    const ReuseFrame f{uint32_t(frame.index), o.render.seed, uint32_t(s)};
    const FrameWorld<Tracer>& fw = world_.view();
    c.begin_frame(world_, ctx_, frame, s);
    c.specular.reserve(size_t(c.width) * size_t(c.height));
    {
      StageTimer timer(frame.stages, "candidates");
      const CandidateStage<Tracer> stage{fw, path_, o.gi.target, f, c.view(), c.reservoirs.data, c.specular.data};
      Exec::for_pixels(c.width, c.height, stage, "ReSTIR GI samples", frame.progress);
    }
    const bool replay = !(ctx_.planted && ctx_.planted->gi_history_cached);
    c.reuse(o.gi.reuse, frame, GiBridges<Tracer>{fw, o.gi.target, path_, replay}, f);
    {
      StageTimer timer(frame.stages, "shading");
      const ShadeStage stage{c.view(), c.reservoirs.data, c.specular.data, o.render.debug_view, c.debug(), sum_.data};
      Exec::for_pixels(c.width, c.height, stage, "ReSTIR GI shading");
    }
    c.end_frame();
  }

  RenderContext ctx_;
  PathOptions path_;
  typename B::World world_;
  std::vector<std::unique_ptr<Chain>> chains_;
  typename Exec::template Array<Rgb> sum_;
};

}  // namespace rl
