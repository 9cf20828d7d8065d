// ReSTIR DI (Bitterli et al. 2020, "Spatiotemporal reservoir resampling for real-time ray tracing
// with dynamic direct lighting"): per pixel, resampled light samples are reused from the previous
// frame and from neighbouring pixels, then shaded with one sample. Direct lighting only (the
// reference is the path tracer at path.max_depth = 1). All resampling math lives in src/restir.
#include <array>

#include "core/parallel.h"
#include "integrators/di_sampling.h"
#include "integrators/gbuffer.h"
#include "restir/mis.h"
#include "restir/neighbors.h"

namespace rl {

namespace {

constexpr int kMaxNeighbors = 64;

// The bridge of mis.h for DI: the identity shift (all domains share the emitters' area measure),
// targets evaluated at each domain's own primary surface.
struct DiBridge {
  const RenderContext& ctx;
  const GSurface* const* surfaces;  // surfaces[i] = domain i's surface, 0 = canonical
  bool canonical_visibility;        // the canonical target includes visibility
  bool other_visibility;            // other domains' targets include visibility
  bool shift_to_canonical(int, const LightPoint& y, LightPoint& x, float& jacobian) const {
    x = y;
    jacobian = 1;
    return true;
  }
  float target_from(int i, const LightPoint& x) const {
    return di_target(ctx, *surfaces[i], x, i == 0 ? canonical_visibility : other_visibility);
  }
};

class RestirDi final : public Integrator {
 public:
  explicit RestirDi(const RenderContext& ctx) : ctx_(ctx) {}

  void render_frame(const FrameInfo& frame, Image& out) override {
    const Options& o = ctx_.options;
    const int spp = o.render.spp;
    if (int(chains_.size()) != spp) chains_.assign(size_t(spp), Chain{});
    std::vector<Rgb> sum(out.size(), Rgb(0));
    for (int s = 0; s < spp; ++s) render_chain(frame, s, chains_[size_t(s)], sum);
    for (size_t i = 0; i < out.size(); ++i) out.pixels[i] = sum[i] / float(spp);
  }

 private:
  // One independent chain of reservoirs per pixel sample (render.spp chains).
  struct Chain {
    GBuffer gbuffer, previous_gbuffer;
    std::vector<DiReservoir> reservoirs, previous;  // current frame / last frame's final reservoirs
    bool has_history = false;
    // Debug views: where each pixel's sample came from (0 own, 1 temporal, 2 spatial) and how
    // many reuse candidates were tried / rejected (reprojection or similarity tests).
    std::vector<uint8_t> source;
    std::vector<uint16_t> tried, rejected;
  };

  void render_chain(const FrameInfo& frame, int s, Chain& c, std::vector<Rgb>& sum) {
    const Options& o = ctx_.options;
    const DiOptions& di = o.di;
    const int w = frame.camera->width(), h = frame.camera->height();
    const uint32_t f = uint32_t(frame.index);
    const uint64_t seed = o.render.seed;
    build_gbuffer(ctx_, *frame.camera, frame.index, s, c.gbuffer);
    const GBuffer& g = c.gbuffer;
    c.reservoirs.assign(size_t(w) * size_t(h), DiReservoir{});
    c.source.assign(c.reservoirs.size(), 0);
    c.tried.assign(c.reservoirs.size(), 0);
    c.rejected.assign(c.reservoirs.size(), 0);

    // 1. Initial candidates.
    parallel_for_pixels(w, h, [&](int x, int y) {
      const uint32_t p = uint32_t(y * w + x);
      Pcg32 rng = make_rng(p, f, RngPass::light_candidates, seed, uint32_t(s));
      c.reservoirs[p] = di_initial_reservoir(ctx_, g.at(x, y), di.light_candidates, di.bsdf_candidates, di.visibility_reuse, rng);
    }, frame.progress);

    // 2. Temporal reuse: the previous frame's final reservoir at the reprojected pixel.
    const PerspectiveCamera* prev_cam = frame.previous_camera ? frame.previous_camera : frame.camera;
    if (di.temporal && c.has_history && c.previous_gbuffer.width == w && c.previous_gbuffer.height == h) {
      std::vector<DiReservoir> next(c.reservoirs.size());
      parallel_for_pixels(w, h, [&](int x, int y) {
        const uint32_t p = uint32_t(y * w + x);
        const GSurface& cur = g.at(x, y);
        next[p] = c.reservoirs[p];
        if (!cur.valid) return;
        ++c.tried[p];
        int px, py;
        if (!reproject(*prev_cam, cur.p, px, py)) {
          ++c.rejected[p];
          return;
        }
        const GSurface& prev = c.previous_gbuffer.at(px, py);
        GSurface expected = cur;  // the current point as the previous camera saw it
        expected.depth = length(cur.p - prev_cam->position());
        if (!similar_surfaces(expected, prev, di.depth_threshold, di.normal_threshold)) {
          ++c.rejected[p];
          return;
        }
        DiReservoir history = c.previous[size_t(py * w + px)];
        history.confidence = restir::capped_confidence(history.confidence, c.reservoirs[p].confidence, float(di.max_history));
        const GSurface* surfaces[2] = {&cur, &prev};
        const DiReservoir* inputs[2] = {&c.reservoirs[p], &history};
        DiBridge bridge{ctx_, surfaces, di.visibility_reuse, di.visibility_reuse && di.neighbor_visibility};
        Pcg32 rng = make_rng(p, f, RngPass::temporal, seed, uint32_t(s));
        restir::CombineInfo info;
        next[p] = restir::combine(bridge, std::span<const DiReservoir* const>(inputs, 2), di.temporal_mis, rng, &info);
        if (info.selected == 1) c.source[p] = 1;
      });
      c.reservoirs.swap(next);
    }

    // 3. Spatial reuse rounds (read one buffer, write the other).
    const int k = std::min(di.spatial_neighbors, kMaxNeighbors);
    for (int round = 0; k > 0 && round < di.spatial_rounds; ++round) {
      std::vector<DiReservoir> next(c.reservoirs.size());
      parallel_for_pixels(w, h, [&](int x, int y) {
        const uint32_t p = uint32_t(y * w + x);
        const GSurface& cur = g.at(x, y);
        next[p] = c.reservoirs[p];
        if (!cur.valid) return;
        Pcg32 rng = make_rng(p, f, RngPass::spatial, seed, uint32_t(s * 16 + round));
        std::array<const GSurface*, kMaxNeighbors + 1> surfaces;
        std::array<const DiReservoir*, kMaxNeighbors + 1> inputs;
        surfaces[0] = &cur;
        inputs[0] = &c.reservoirs[p];
        int n = 1;
        const float rotation = rng.next_float();
        for (int j = 0; j < k; ++j) {
          Vec2 off = restir::spatial_offset(j, k, di.spatial_radius, rotation);
          int nx = x + int(std::lround(off.x)), ny = y + int(std::lround(off.y));
          ++c.tried[p];
          const bool inside = !(nx == x && ny == y) && nx >= 0 && ny >= 0 && nx < w && ny < h;
          if (!inside || !g.at(nx, ny).valid ||
              (di.similarity_rejection && !similar_surfaces(cur, g.at(nx, ny), di.depth_threshold, di.normal_threshold))) {
            ++c.rejected[p];
            continue;
          }
          const GSurface& ns = g.at(nx, ny);
          surfaces[size_t(n)] = &ns;
          inputs[size_t(n)] = &c.reservoirs[size_t(ny * w + nx)];
          ++n;
        }
        DiBridge bridge{ctx_, surfaces.data(), di.visibility_reuse, di.visibility_reuse && di.neighbor_visibility};
        restir::CombineInfo info;
        next[p] = restir::combine(bridge, std::span<const DiReservoir* const>(inputs.data(), size_t(n)), di.spatial_mis, rng, &info);
        if (info.selected > 0) c.source[p] = 2;
      });
      c.reservoirs.swap(next);
    }

    // 4. Shading: f(y) W, with visibility traced unless the target already included it.
    const float eps = ctx_.accel.ray_epsilon();
    parallel_for_pixels(w, h, [&](int x, int y) {
      const uint32_t p = uint32_t(y * w + x);
      const GSurface& sf = g.at(x, y);
      switch (o.render.debug_view) {
        case DebugView::none:
          break;
        case DebugView::confidence:
          sum[p] += Rgb(c.reservoirs[p].confidence);
          return;
        case DebugView::reuse_source:
          sum[p] += Rgb(float(c.source[p]));
          return;
        case DebugView::rejected_shifts:
          sum[p] += Rgb(c.tried[p] ? float(c.rejected[p]) / float(c.tried[p]) : 0.0f);
          return;
      }
      Rgb L = sf.valid ? sf.emitted : sf.background;
      if (sf.valid) {
        if (bsdf_is_delta(sf.bsdf)) {
          Pcg32 rng = make_rng(p, f, RngPass::misc, seed, uint32_t(s));
          L += di_specular(ctx_, sf, rng);
        } else if (c.reservoirs[p].has_sample()) {
          Ray shadow;
          Rgb contrib = di_unshadowed(ctx_.lights, sf, c.reservoirs[p].sample, eps, &shadow) * c.reservoirs[p].ucw;
          if (!di.visibility_reuse && ctx_.accel.occluded(shadow)) contrib = Rgb(0);
          L += contrib;
        }
      }
      sum[p] += L;
    });

    // 5. Keep this frame's reservoirs and surfaces for the next frame's temporal reuse.
    c.previous.swap(c.reservoirs);
    std::swap(c.previous_gbuffer, c.gbuffer);
    c.has_history = true;
  }

  RenderContext ctx_;
  std::vector<Chain> chains_;
};

}  // namespace

std::unique_ptr<Integrator> make_restir_di(const RenderContext& ctx) { return std::make_unique<RestirDi>(ctx); }

}  // namespace rl
