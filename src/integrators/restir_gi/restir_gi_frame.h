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

// A pixel's initial sample, and its light that is not resampled (direct light, or a plain path
// through a delta BSDF) into specular[p].
template <class Tracer>
struct Sampler {
  FrameWorld<Tracer> fw;
  PathOptions path;  // the secondary path's: path.max_depth - 1 bounces
  GiTarget kind;
  ReuseFrame f;
  Rgb* specular;
  RESTIR_HD GiReservoir operator()(const GSurface& s, int, int, uint32_t p) const {
    Pcg32 rng = make_rng(p, f.frame, RngPass::path, f.seed, f.chain);
    Rgb spec(0);
    const GiReservoir r = gi_initial(fw.world, fw.tracer, path, kind, s, rng, spec);
    specular[p] = spec + gi_direct(fw.world, fw.tracer, s, rng);
    return r;
  }
};

struct Shader {
  const Rgb* specular;
  RESTIR_HD Rgb operator()(const GSurface& s, const GiReservoir& r, uint32_t p) const { return gi_shade(s, r, specular[p]); }
};

}  // namespace gi_frame_detail

template <class B>
struct RestirGiChain : ReservoirChain<B, GiReservoir> {
  typename B::Exec::template Array<Rgb> specular;  // not resampled: direct light, or a plain path through a delta BSDF
  size_t bytes() const { return ReservoirChain<B, GiReservoir>::bytes() + array_bytes(specular); }
};

template <class B>
class RestirGiFrame final : public ReservoirFrame<B, RestirGiChain<B>> {
  using Base = ReservoirFrame<B, RestirGiChain<B>>;
  using Chain = RestirGiChain<B>;
  using typename Base::Tracer;
  using Base::ctx_;
  using Base::world_;

 public:
  explicit RestirGiFrame(const RenderContext& ctx) : Base(ctx), path_(ctx.options.path) {
    path_.max_depth = ctx.options.path.max_depth - 1;  // the sample point's radiance: one bounce less
  }

  // The previous frame's scene and BVH for temporal reuse in an animated scene (GiBridge).
  bool needs_previous_scene() const override { return scene_animated(ctx_.scene) && ctx_.options.gi.reuse.temporal; }

 private:
  void render_chain(const FrameInfo& frame, const ReuseFrame& f, Chain& c) override {
    using namespace gi_frame_detail;
    const Options& o = ctx_.options;
    const FrameWorld<Tracer>& fw = this->fw();
    c.specular.reserve(size_t(c.width) * size_t(c.height));
    this->template candidates<GiReservoir>(frame, c, Sampler<Tracer>{fw, path_, o.gi.target, f, c.specular.data}, "ReSTIR GI samples");
    const bool replay = !(ctx_.planted && ctx_.planted->gi_history_cached);
    c.reuse(o.gi.reuse, frame, GiBridges<Tracer>{fw, o.gi.target, path_, replay}, f, ctx_.planted);
    this->template shade<GiReservoir>(frame, c, Shader{c.specular.data}, "ReSTIR GI shading");
  }

  PathOptions path_;
};

}  // namespace rl
