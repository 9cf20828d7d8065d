// The one temporal and the one spatial reuse pass shared by the ReSTIR integrators (DI, PT).
// They own the pixel bookkeeping — reprojection, neighbour choice, similarity rejection, M-cap,
// debug counters — and hand the resampling to restir::combine() through the integrator's bridge.
// A bridge is made per pixel from the surfaces of the inputs (index 0 = the canonical pixel).
#pragma once
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/parallel.h"
#include "integrators/gbuffer.h"
#include "integrators/options.h"
#include "restir/mis.h"
#include "restir/neighbors.h"

namespace rl {


// Per-pixel diagnostics behind render.debug_view.
struct ReuseDebug {
  std::vector<uint8_t> source;             // 0 own sample, 1 temporal, 2 spatial
  std::vector<uint16_t> tried, rejected;   // reuse candidates considered / rejected (or shift failed)
  void reset(size_t n) {
    source.assign(n, 0);
    tried.assign(n, 0);
    rejected.assign(n, 0);
  }
  float rejected_fraction(size_t p) const { return tried[p] ? float(rejected[p]) / float(tried[p]) : 0.0f; }
};

inline constexpr int kMaxReuseNeighbors = 64;

// The non-finite policy of every integrator: a reservoir that met a NaN or infinite target makes
// its pixel NaN, and the render driver reports the frame's non-finite pixels (render.cpp).
template <class Sample>
void mark_non_finite(const restir::Reservoir<Sample>& r, Rgb& L) {
  if (r.non_finite()) L = Rgb(std::numeric_limits<float>::quiet_NaN());
}

// The value render.debug_view shows for pixel p; false for DebugView::none (shade normally).
// reconnection_depth: the final sample's reconnection vertex, for integrators that have one
// (ReSTIR PT); the others reject that view when they are made.
template <class Sample>
bool debug_view_value(DebugView view, const restir::Reservoir<Sample>& r, const ReuseDebug& dbg, size_t p, Rgb& out,
                      int reconnection_depth = 0) {
  switch (view) {
    case DebugView::none: return false;
    case DebugView::confidence: out = Rgb(r.confidence); return true;
    case DebugView::reuse_source: out = Rgb(float(dbg.source[p])); return true;
    case DebugView::rejected_shifts: out = Rgb(dbg.rejected_fraction(p)); return true;
    case DebugView::reconnection_depth: out = Rgb(float(reconnection_depth)); return true;
  }
  return false;
}

// Temporal reuse: combine each pixel's reservoir with last frame's final reservoir at the
// reprojected pixel (if that surface is similar), history confidence capped (M-cap).
template <class Sample, class MakeBridge>
void temporal_pass(const ReuseOptions& rp, const GBuffer& g, const GBuffer& previous_g, const PerspectiveCamera& previous_camera,
                   std::vector<restir::Reservoir<Sample>>& reservoirs, const std::vector<restir::Reservoir<Sample>>& history,
                   std::vector<restir::Reservoir<Sample>>& next, const MakeBridge& make_bridge, uint32_t frame, uint64_t seed,
                   uint32_t chain, ReuseDebug& dbg) {
  using Res = restir::Reservoir<Sample>;
  const int w = g.width, h = g.height;
  next.resize(reservoirs.size());  // the chain's scratch buffer: allocated once per frame size
  parallel_for_pixels(w, h, [&](int x, int y) {
    const uint32_t p = uint32_t(y * w + x);
    const GSurface& cur = g.at(x, y);
    next[p] = reservoirs[p];
    if (!cur.valid) return;
    ++dbg.tried[p];
    int px, py;
    // Motion vector: where the point was a frame earlier (its object's animation), seen by the
    // previous camera.
    if (!reproject(previous_camera, cur.p_previous, px, py)) {
      ++dbg.rejected[p];
      return;
    }
    const GSurface& prev = previous_g.at(px, py);
    GSurface expected = cur;  // the current point as the previous camera saw it
    expected.p = cur.p_previous;
    expected.ns = cur.ns_previous;
    expected.depth = length(cur.p_previous - previous_camera.position());
    // Depth / normal rejection only when asked for (*.similarity_rejection), as in the spatial pass.
    if (!prev.valid || (rp.similarity_rejection && !similar_surfaces(expected, prev, rp.depth_threshold, rp.normal_threshold))) {
      ++dbg.rejected[p];
      return;
    }
    Res hist = history[size_t(py * w + px)];
    hist.confidence = restir::capped_confidence(hist.confidence, reservoirs[p].confidence, float(rp.max_history));
    const GSurface* surfaces[2] = {&cur, &prev};
    const Res* inputs[2] = {&reservoirs[p], &hist};
    auto bridge = make_bridge(surfaces, 2, true);
    Pcg32 rng = make_rng(p, frame, RngPass::temporal, seed, chain);
    restir::CombineInfo info;
    next[p] = restir::combine(bridge, std::span<const Res* const>(inputs, 2), rp.temporal_mis, rng, &info);
    dbg.rejected[p] += uint16_t(info.failed_shifts);
    if (info.selected == 1) dbg.source[p] = 1;
  });
  reservoirs.swap(next);
}

// Spatial reuse rounds: each pixel combines its reservoir with those of up to spatial_neighbors
// pixels on a rotated golden-angle spiral within spatial_radius (reading one buffer, writing the other).
template <class Sample, class MakeBridge>
void spatial_passes(const ReuseOptions& rp, const GBuffer& g, std::vector<restir::Reservoir<Sample>>& reservoirs,
                    std::vector<restir::Reservoir<Sample>>& next, const MakeBridge& make_bridge, uint32_t frame,
                    uint64_t seed, uint32_t chain, ReuseDebug& dbg) {
  using Res = restir::Reservoir<Sample>;
  const int w = g.width, h = g.height;
  const int k = std::min(rp.spatial_neighbors, kMaxReuseNeighbors);
  for (int round = 0; k > 0 && round < rp.spatial_rounds; ++round) {
    next.resize(reservoirs.size());  // the chain's scratch buffer (every pixel is written below)
    parallel_for_pixels(w, h, [&](int x, int y) {
      const uint32_t p = uint32_t(y * w + x);
      const GSurface& cur = g.at(x, y);
      next[p] = reservoirs[p];
      if (!cur.valid) return;
      Pcg32 rng = make_rng(p, frame, RngPass::spatial, seed, chain * 16u + uint32_t(round));
      std::array<const GSurface*, kMaxReuseNeighbors + 1> surfaces;
      std::array<const Res*, kMaxReuseNeighbors + 1> inputs;
      surfaces[0] = &cur;
      inputs[0] = &reservoirs[p];
      int n = 1;
      const float rotation = rng.next_float();
      for (int j = 0; j < k; ++j) {
        Vec2 off = restir::spatial_offset(j, k, rp.spatial_radius, rotation);
        int nx = x + int(std::lround(off.x)), ny = y + int(std::lround(off.y));
        ++dbg.tried[p];
        const bool inside = !(nx == x && ny == y) && nx >= 0 && ny >= 0 && nx < w && ny < h;
        if (!inside || !g.at(nx, ny).valid ||
            (rp.similarity_rejection && !similar_surfaces(cur, g.at(nx, ny), rp.depth_threshold, rp.normal_threshold))) {
          ++dbg.rejected[p];
          continue;
        }
        surfaces[size_t(n)] = &g.at(nx, ny);
        inputs[size_t(n)] = &reservoirs[size_t(ny * w + nx)];
        ++n;
      }
      auto bridge = make_bridge(surfaces.data(), n, false);
      restir::CombineInfo info;
      next[p] = restir::combine(bridge, std::span<const Res* const>(inputs.data(), size_t(n)), rp.spatial_mis, rng, &info);
      dbg.rejected[p] += uint16_t(info.failed_shifts);
      if (info.selected > 0) dbg.source[p] = 2;
    });
    reservoirs.swap(next);
  }
}

// One chain of reservoirs of a ReSTIR integrator (one per pixel sample, render.spp chains): this
// frame's and last frame's surfaces and reservoirs, and the reuse bookkeeping around them.
template <class Sample>
struct ReservoirChain {
  GBuffer gbuffer, previous_gbuffer;
  std::vector<restir::Reservoir<Sample>> reservoirs, previous;
  std::vector<restir::Reservoir<Sample>> scratch;  // a reuse pass's output, swapped with reservoirs
  bool has_history = false;
  ReuseDebug debug;

  // Primary hits of chain `s` of this frame, empty reservoirs.
  void begin_frame(const RenderContext& ctx, const FrameInfo& frame, int s) {
    StageTimer timer(frame.stages, "primary");
    build_gbuffer(ctx, *frame.camera, frame.index, s, gbuffer);
    reservoirs.assign(gbuffer.pixels.size(), restir::Reservoir<Sample>{});
    debug.reset(reservoirs.size());
  }
  // Temporal reuse (when there is a compatible history), then the spatial rounds.
  template <class MakeBridge>
  void reuse(const ReuseOptions& rp, const FrameInfo& frame, const MakeBridge& make_bridge, uint64_t seed, int s) {
    const uint32_t f = uint32_t(frame.index), chain = uint32_t(s);
    const PerspectiveCamera& prev_cam = frame.previous_camera ? *frame.previous_camera : *frame.camera;
    if (rp.temporal && has_history && previous_gbuffer.width == gbuffer.width && previous_gbuffer.height == gbuffer.height) {
      StageTimer timer(frame.stages, "temporal");
      temporal_pass(rp, gbuffer, previous_gbuffer, prev_cam, reservoirs, previous, scratch, make_bridge, f, seed, chain, debug);
    }
    StageTimer timer(frame.stages, "spatial");
    spatial_passes(rp, gbuffer, reservoirs, scratch, make_bridge, f, seed, chain, debug);
  }
  // Keeps this frame's reservoirs and surfaces for the next frame's temporal reuse.
  void end_frame() {
    previous.swap(reservoirs);
    std::swap(previous_gbuffer, gbuffer);
    has_history = true;
  }
};

// Renders every chain (render_chain(s, chain, sum) adds chain s's radiance to sum) and averages.
template <class Chain, class RenderChain>
void render_chains(std::vector<Chain>& chains, int spp, Image& out, const RenderChain& render_chain) {
  if (int(chains.size()) != spp) chains.assign(size_t(spp), Chain{});
  std::vector<Rgb> sum(out.size(), Rgb(0));
  for (int s = 0; s < spp; ++s) render_chain(s, chains[size_t(s)], sum);
  for (size_t i = 0; i < out.size(); ++i) out.pixels[i] = sum[i] / float(spp);
}

}  // namespace rl
