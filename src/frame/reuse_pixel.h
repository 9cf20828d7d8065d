// One pixel of the temporal and of the spatial reuse pass shared by the ReSTIR integrators,
// RESTIR_HD over flat buffers: the one reservoir chain (reservoir_chain.h) runs them through its
// backend's policy -- a loop over the pixels on the host, one thread per pixel in the CUDA
// backend's kernels. They own the pixel bookkeeping --
// reprojection, neighbour choice, similarity rejection, M-cap, debug counters -- and hand the
// resampling to restir::combine() through the integrator's bridge, made per pixel from the
// surfaces of the inputs (SurfaceList, index 0 = the canonical pixel) by make_bridge(surfaces, n, temporal).
#pragma once
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>

#include "core/rng.h"
#include "frame/gbuffer.h"
#include "frame/options.h"
#include "frame/ray_slots.h"
#include "restir/mis.h"
#include "restir/neighbors.h"

namespace rl {

inline constexpr int kMaxReuseNeighbors = 64;

// A frame's G-buffer as flat memory. motion: GBuffer::motion, null in a static scene.
struct GBufferView {
  const GPacked* pixels = nullptr;
  int width = 0, height = 0;
  const GMotion* motion = nullptr;
  const MaterialParams* materials = nullptr;  // the scene's: GSurface::bsdf is made from them
  const Rgb* emitted = nullptr;               // the emission toward the camera; null: 0 (a previous frame's)
  Vec3 eye;                                   // the position of the camera that saw them
  RESTIR_HD size_t index(int x, int y) const { return size_t(y) * size_t(width) + size_t(x); }
  // Pixel i's surface, unpacked (unpack_surface: a value, not a reference into the buffer).
  RESTIR_HD GSurface surface(size_t i) const { return unpack_surface(pixels[i], materials, eye, emitted ? emitted[i] : Rgb(0)); }
  RESTIR_HD GSurface at(int x, int y) const { return surface(index(x, y)); }
  RESTIR_HD const GPacked& packed(int x, int y) const { return pixels[index(x, y)]; }
  RESTIR_HD GMotion motion_at(int x, int y) const { return motion_of(pixels, motion, index(x, y)); }
};
inline GBufferView view_of(const GBuffer& g) {
  return {g.pixels.data(), g.width, g.height, g.motion_data(), g.materials.data(), g.emitted.empty() ? nullptr : g.emitted.data(), g.eye};
}

// Per-pixel diagnostics behind render.debug_view (ReuseDebug's arrays, or the device's).
struct ReuseDebugView {
  uint8_t* source;             // 0 own sample, 1 temporal, 2 spatial
  uint16_t* tried, *rejected;  // reuse candidates considered / rejected (or shift failed)
  RESTIR_HD float rejected_fraction(size_t p) const { return tried[p] ? float(rejected[p]) / float(tried[p]) : 0.0f; }
};

// RGB resampling weights (mis.h, CombineInfo::color; *.rgb_weights): where a spatial round
// writes each pixel's shading colour Σ_i m_i F(Y_i) W_i |∂T_i| (null: not asked for), and, for
// paired reuse, F of each pass-1 shift (indexed as its PairedShift). planted_input_target: tests
// only (PlantedBias::color_input_target).
struct ReuseColor {
  Rgb* out = nullptr;
  Rgb* shifts = nullptr;
  bool planted_input_target = false;
};

// Which random streams a pass reads: frame, render seed, chain (pixel sample).
struct ReuseFrame {
  uint32_t frame = 0;
  uint64_t seed = 0;
  uint32_t chain = 0;
  bool planted_ratio_canonical = false;  // tests only: PlantedBias::ratio_canonical_symmetric
};

// The MIS weights a reuse pass resamples with: rp's choice `kind` and its ratio exponent.
RESTIR_HD inline restir::MisWeights reuse_weights(restir::ReuseMis kind, const ReuseOptions& rp, const ReuseFrame& f) {
  return restir::MisWeights(kind, rp.mis_ratio_exponent, f.planted_ratio_canonical);
}

// Pixel p's random stream in spatial round `round` (its first number rotates the neighbour spiral):
// the one key spatial_pixel and its look-ahead prefetch both draw from.
RESTIR_HD inline Pcg32 spatial_stream(const ReuseFrame& f, int round, uint32_t p) {
  return make_rng(p, f.frame, RngPass::spatial, f.seed, f.chain * 16u + uint32_t(round));
}

// The non-finite policy of every integrator: a reservoir that met a NaN or infinite target makes
// its pixel NaN, and the render driver reports the frame's non-finite pixels (render.cpp).
template <class Sample>
RESTIR_HD void mark_non_finite(const restir::Reservoir<Sample>& r, Rgb& L) {
  if (r.non_finite()) L = Rgb(std::numeric_limits<float>::quiet_NaN());
}

// The reconnection vertex of a reservoir's sample, for the reconnection-depth debug view: none
// (0) for samples without a path; ReSTIR PT's paths overload it (restir_pt_pixel.h).
template <class Res>
RESTIR_HD int reconnection_depth_of(const Res&) {
  return 0;
}

// The value render.debug_view shows for pixel p; false for DebugView::none (shade normally).
// reconnection_depth: the final sample's reconnection vertex, for integrators that have one
// (ReSTIR PT); the others reject that view when they are made.
template <class Sample>
RESTIR_HD bool debug_view_value(DebugView view, const restir::Reservoir<Sample>& r, const ReuseDebugView& dbg, size_t p, Rgb& out,
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

// The shading stages' prologue: with a debug view on, adds its value to sum[p] and returns true
// (the stage shades nothing); with none, returns false.
template <class Sample>
RESTIR_HD bool add_debug_view(DebugView view, const restir::Reservoir<Sample>& r, const ReuseDebugView& dbg, size_t p, Rgb* sum,
                              int reconnection_depth = 0) {
  Rgb d;
  if (!debug_view_value(view, r, dbg, p, d, reconnection_depth)) return false;
  sum[p] += d;
  return true;
}

// cursor (both passes): a queued pass's producer or consumer run of the pixel (ray_slots.h), whose
// bridge is make_bridge(surfaces, n, temporal, cursor); nullptr (a type of its own): the inline
// pass, make_bridge(surfaces, n, temporal), its shadow rays traced by the pixel's thread.
template <class MakeBridge>
RESTIR_HD auto bridge_for(const MakeBridge& make_bridge, const SurfaceList& surfaces, int n, bool temporal, std::nullptr_t) {
  return make_bridge(surfaces, n, temporal);
}
template <class MakeBridge>
RESTIR_HD auto bridge_for(const MakeBridge& make_bridge, const SurfaceList& surfaces, int n, bool temporal, RayCursor* cursor) {
  return make_bridge(surfaces, n, temporal, cursor);
}

// Temporal reuse at pixel (x, y): its reservoir combined with last frame's final reservoir at the
// reprojected pixel (if that surface is similar), the history's confidence capped (M-cap), into next.
// history_caps: per previous-frame pixel, the M-cap the duplication map set (null: rp.max_history).
template <class Res, class MakeBridge, class Cursor = std::nullptr_t>
RESTIR_HD RESTIR_FORCE_INLINE void temporal_pixel(const ReuseOptions& rp, const GBufferView& g, const GBufferView& previous_g,
                              const PerspectiveCamera& previous_camera, const Res* reservoirs, const Res* history, Res* next,
                              const MakeBridge& make_bridge, const ReuseFrame& f, const ReuseDebugView& dbg, int x, int y,
                              const float* history_caps = nullptr, Cursor cursor = nullptr) {
  const uint32_t p = uint32_t(y * g.width + x);
  const GSurface cur = g.at(x, y);
  next[p] = reservoirs[p];
  if (!cur.valid) return;
  ++dbg.tried[p];
  int px, py;
  // Motion vector: where the point was a frame earlier (its object's animation), seen by the
  // previous camera.
  const GMotion motion = g.motion_at(x, y);
  if (!reproject(previous_camera, motion.p_previous, px, py)) {
    ++dbg.rejected[p];
    return;
  }
  const GPacked& prev = previous_g.packed(px, py);  // unpacked by the bridge where it reads it
  // The current point as the previous camera saw it: its depth and normal there.
  const float expected_depth = length(motion.p_previous - previous_camera.position());
  // Depth / normal rejection only when asked for (*.similarity_rejection), as in the spatial pass.
  if (!prev.valid() ||
      (rp.similarity_rejection && !similar_surfaces(expected_depth, motion.ns_previous, prev, rp.depth_threshold, rp.normal_threshold))) {
    ++dbg.rejected[p];
    return;
  }
  Res hist = history[size_t(py * g.width + px)];
  const float cap = history_caps ? history_caps[size_t(py * g.width + px)] : float(rp.max_history);
  hist.confidence = restir::capped_confidence(hist.confidence, reservoirs[p].confidence, cap);
  const GPacked* packed[2] = {nullptr, &prev};
  const Res* inputs[2] = {&reservoirs[p], &hist};
  auto bridge = bridge_for(make_bridge, SurfaceList{&cur, packed, g.materials, previous_g.eye}, 2, true, cursor);
  Pcg32 rng = make_rng(p, f.frame, RngPass::temporal, f.seed, f.chain);
  restir::CombineInfo info;
  next[p] = restir::combine(bridge, std::span<const Res* const>(inputs, 2), reuse_weights(rp.temporal_mis, rp, f), rng, &info);
  dbg.rejected[p] += uint16_t(info.failed_shifts);
  if (info.selected == 1) dbg.source[p] = 1;
}

// Pixel (x, y)'s k neighbour positions in a spatial round: a golden-angle spiral within
// spatial_radius, rotated by `rotation` (the first number of the pixel's spatial stream).
RESTIR_HD inline void spatial_positions(float radius, int k, float rotation, int x, int y, int* nxs, int* nys) {
  for (int j = 0; j < k; ++j) {
    const Vec2 off = restir::spatial_offset(j, k, radius, rotation);
    nxs[j] = x + int(lroundf(off.x)), nys[j] = y + int(lroundf(off.y));
  }
}

#ifndef __CUDA_ARCH__
// Fetches every cache line of [p, p + bytes), from the line p starts in: an entry that starts late
// in a line spans one line more than bytes / 64.
inline void prefetch_lines(const void* p, size_t bytes) {
  const uintptr_t first = reinterpret_cast<uintptr_t>(p) & ~uintptr_t(63);
  const uintptr_t end = reinterpret_cast<uintptr_t>(p) + bytes;
  for (uintptr_t a = first; a < end; a += 64) prefetch_line(reinterpret_cast<const void*>(a));
}

// Fetches the G-buffer entries and reservoirs of the neighbours inside the image.
template <class Res>
inline void prefetch_neighbours(const GBufferView& g, const Res* reservoirs, int k, const int* nxs, const int* nys) {
  for (int j = 0; j < k; ++j) {
    if (nxs[j] < 0 || nys[j] < 0 || nxs[j] >= g.width || nys[j] >= g.height) continue;
    prefetch_lines(&g.packed(nxs[j], nys[j]), sizeof(GPacked));
    prefetch_lines(&reservoirs[size_t(nys[j]) * size_t(g.width) + size_t(nxs[j])], sizeof(Res));
  }
}
#endif

// Spatial reuse round `round` at pixel (x, y): its reservoir combined with those of up to
// spatial_neighbors pixels on a rotated golden-angle spiral within spatial_radius, into next.
template <class Res, class MakeBridge, class Cursor = std::nullptr_t>
RESTIR_HD RESTIR_FORCE_INLINE void spatial_pixel(const ReuseOptions& rp, const GBufferView& g, const Res* reservoirs, Res* next, const MakeBridge& make_bridge,
                             const ReuseFrame& f, int round, const ReuseDebugView& dbg, int x, int y, const ReuseColor& color = {},
                             Cursor cursor = nullptr) {
  const int w = g.width, h = g.height;
  const int k = rp.spatial_neighbors < kMaxReuseNeighbors ? rp.spatial_neighbors : kMaxReuseNeighbors;
  const uint32_t p = uint32_t(y * w + x);
  const GSurface cur = g.at(x, y);
  next[p] = reservoirs[p];
  if (color.out) color.out[p] = Rgb(0);
  if (!cur.valid) return;
  Pcg32 rng = spatial_stream(f, round, p);
  const GPacked* packed[kMaxReuseNeighbors + 1];
  const Res* inputs[kMaxReuseNeighbors + 1];
  packed[0] = nullptr;
  inputs[0] = &reservoirs[p];
  int n = 1;
  int nxs[kMaxReuseNeighbors], nys[kMaxReuseNeighbors];
  spatial_positions(rp.spatial_radius, k, rng.next_float(), x, y, nxs, nys);
#ifndef __CUDA_ARCH__
  // The neighbours' G-buffer entries and reservoirs are up to spatial_radius rows away: cache
  // misses that were half of this function's time (ReSTIR PT). Fetching all of them before the
  // first is read overlaps the misses with each other; fetching the next pixel's (x + 1, the next
  // one in a tile row, from its own stream's rotation) overlaps them with this pixel's shifts too.
  prefetch_neighbours(g, reservoirs, k, nxs, nys);
  if (x + 1 < w) {
    Pcg32 ahead = spatial_stream(f, round, p + 1);
    int axs[kMaxReuseNeighbors], ays[kMaxReuseNeighbors];
    spatial_positions(rp.spatial_radius, k, ahead.next_float(), x + 1, y, axs, ays);
    prefetch_neighbours(g, reservoirs, k, axs, ays);
  }
#endif
  for (int j = 0; j < k; ++j) {
    const int nx = nxs[j], ny = nys[j];
    ++dbg.tried[p];
    const bool inside = !(nx == x && ny == y) && nx >= 0 && ny >= 0 && nx < w && ny < h;
    if (!inside || !g.packed(nx, ny).valid() ||
        (rp.similarity_rejection && !similar_surfaces(cur, g.packed(nx, ny), rp.depth_threshold, rp.normal_threshold))) {
      ++dbg.rejected[p];
      continue;
    }
    packed[n] = &g.packed(nx, ny);
    inputs[n] = &reservoirs[size_t(ny * w + nx)];
    ++n;
  }
  auto bridge = bridge_for(make_bridge, SurfaceList{&cur, packed, g.materials, g.eye}, n, false, cursor);
  restir::CombineInfo info;
  info.want_color = color.out != nullptr;
  info.color_input_target = color.planted_input_target;
  next[p] = restir::combine(bridge, std::span<const Res* const>(inputs, size_t(n)), reuse_weights(rp.spatial_mis, rp, f), rng, &info);
  if (color.out) color.out[p] = info.color;
  dbg.rejected[p] += uint16_t(info.failed_shifts);
  if (info.selected > 0) dbg.source[p] = 2;
}

}  // namespace rl
