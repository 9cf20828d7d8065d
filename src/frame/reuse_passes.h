// The one temporal and the one spatial reuse pass shared by the ReSTIR integrators (DI, PT).
// They own the pixel bookkeeping — reprojection, neighbour choice, similarity rejection, M-cap,
// debug counters — and hand the resampling to restir::combine() through the integrator's bridge.
// A bridge is made per pixel from the surfaces of the inputs (index 0 = the canonical pixel).
#pragma once
#include <cstdint>
#include <limits>
#include <vector>

#include "core/parallel.h"
#include "frame/gbuffer.h"
#include "frame/options.h"
#include "frame/reuse_pixel.h"

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
  ReuseDebugView view() { return {source.data(), tried.data(), rejected.data()}; }
};

// Temporal reuse over the frame (temporal_pixel, reuse_pixel.h, at every pixel), then the
// output swapped in as the reservoirs.
template <class Sample, class MakeBridge>
void temporal_pass(const ReuseOptions& rp, const GBuffer& g, const GBuffer& previous_g, const PerspectiveCamera& previous_camera,
                   std::vector<restir::Reservoir<Sample>>& reservoirs, const std::vector<restir::Reservoir<Sample>>& history,
                   std::vector<restir::Reservoir<Sample>>& next, const MakeBridge& make_bridge, uint32_t frame, uint64_t seed,
                   uint32_t chain, ReuseDebug& dbg) {
  next.resize(reservoirs.size());  // the chain's scratch buffer: allocated once per frame size
  const ReuseFrame f{frame, seed, chain};
  const ReuseDebugView dv = dbg.view();
  parallel_for_pixels(g.width, g.height, [&](int x, int y) {
    temporal_pixel(rp, view_of(g), view_of(previous_g), previous_camera, reservoirs.data(), history.data(), next.data(), make_bridge,
                   f, dv, x, y);
  });
  reservoirs.swap(next);
}

// The spatial reuse rounds (spatial_pixel at every pixel, reading one buffer, writing the other).
template <class Sample, class MakeBridge>
void spatial_passes(const ReuseOptions& rp, const GBuffer& g, std::vector<restir::Reservoir<Sample>>& reservoirs,
                    std::vector<restir::Reservoir<Sample>>& next, const MakeBridge& make_bridge, uint32_t frame,
                    uint64_t seed, uint32_t chain, ReuseDebug& dbg) {
  const ReuseFrame f{frame, seed, chain};
  const ReuseDebugView dv = dbg.view();
  for (int round = 0; rp.spatial_neighbors > 0 && round < rp.spatial_rounds; ++round) {
    next.resize(reservoirs.size());  // the chain's scratch buffer (every pixel is written below)
    parallel_for_pixels(g.width, g.height, [&](int x, int y) {
      spatial_pixel(rp, view_of(g), reservoirs.data(), next.data(), make_bridge, f, round, dv, x, y);
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

  // Primary hits of chain `s` of this frame; the reservoirs sized for them.
  void begin_frame(const RenderContext& ctx, const FrameInfo& frame, int s) {
    StageTimer timer(frame.stages, "primary");
    build_gbuffer(ctx, *frame.camera, frame.index, s, gbuffer);
    // Sized, not cleared: every integrator's candidate stage writes every pixel's reservoir before
    // anything reads it, and clearing ~300 MB of path reservoirs (1280x720) on one thread cost
    // tens of ms a frame.
    reservoirs.resize(gbuffer.pixels.size());
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
