// The one chain of reservoirs of a ReSTIR frame, written once for every backend (cpu_backend.h):
// one pixel sample's G-buffer and reservoirs, this frame's and last frame's, in the backend's
// memory, and the stages every ReSTIR integrator shares around its own -- primary hits, temporal
// reuse, the spatial rounds -- with reuse_pixel.h's per-pixel bookkeeping; then the chains' average.
// An integrator's frame (restir_di_frame.h, restir_gi_frame.h, restir_pt_frame.h) adds its
// candidates and shading between them.
#pragma once
#include <memory>
#include <vector>

#include "frame/integrator.h"
#include "frame/paired_reuse.h"
#include "frame/reuse_pixel.h"

namespace rl {

namespace chain_detail {

template <class Res, class Bridges>
struct TemporalStage {
  Bridges bridges;
  ReuseOptions rp;
  GBufferView g, previous_g;
  PerspectiveCamera previous_camera;
  const Res *reservoirs, *history;
  Res* next;
  ReuseFrame f;
  ReuseDebugView dbg;
  const float* history_caps;  // the duplication map's M-caps (null: off)
  template <class Cursor>
  RESTIR_HD RESTIR_FORCE_INLINE void run(int x, int y, Cursor cursor) const {
    temporal_pixel(rp, g, previous_g, previous_camera, reservoirs, history, next, bridges, f, dbg, x, y, history_caps, cursor);
  }
  RESTIR_HD RESTIR_FORCE_INLINE void operator()(int x, int y) const { run(x, y, nullptr); }
};

template <class Res, class Bridges>
struct SpatialStage {
  Bridges bridges;
  ReuseOptions rp;
  GBufferView g;
  const Res* reservoirs;
  Res* next;
  ReuseFrame f;
  int round;
  ReuseDebugView dbg;
  ReuseColor color;
  template <class Cursor>
  RESTIR_HD RESTIR_FORCE_INLINE void run(int x, int y, Cursor cursor) const {
    spatial_pixel(rp, g, reservoirs, next, bridges, f, round, dbg, x, y, color, cursor);
  }
  RESTIR_HD RESTIR_FORCE_INLINE void operator()(int x, int y) const { run(x, y, nullptr); }
};

// A queued reuse pass (render.reuse_rays = queued, ray_slots.h): pass's pixel run as the producer,
// which records its shadow rays, or as the consumer, which reads their answers. The producer's
// outputs are overwritten by the consumer's, but for the debug counters, which a pass increments:
// the producer puts them back.
template <class Pass>
struct QueuedPassStage {
  Pass pass;
  RaySlotsView slots;
  bool record;
  RESTIR_HD RESTIR_FORCE_INLINE void operator()(int x, int y) const {
    const uint32_t p = uint32_t(y * pass.g.width + x);
    RayCursor cursor{slots, p, record};
    if (!record) return pass.run(x, y, &cursor);
    const ReuseDebugView& dbg = pass.dbg;
    const uint8_t source = dbg.source[p];
    const uint16_t tried = dbg.tried[p], rejected = dbg.rejected[p];
    pass.run(x, y, &cursor);
    dbg.source[p] = source, dbg.tried[p] = tried, dbg.rejected[p] = rejected;
    cursor.finish();
  }
};

// Paired spatial reuse (paired_reuse.h): pass 1, each pixel's sample shifted to its partners.
template <class Res, class Bridges>
struct PairedShiftStage {
  Bridges bridges;
  ReuseOptions rp;
  GBufferView g;
  const Res* reservoirs;
  PairedShift* shifts;
  PairedRound round;
  ReuseColor color;
  uint8_t* deferred;  // replay compaction: flags of the shifts left to PairedReplayStage (null: none)
  RESTIR_HD void operator()(int x, int y) const { paired_shift_pixel(rp, g, reservoirs, shifts, bridges, round, x, y, color, deferred); }
};

// Replay compaction (pt.replay_compaction): the slots pass 1 deferred, listed, then shifted.
struct DeferredSlot {
  const uint8_t* deferred;
  RESTIR_HD bool operator()(size_t i) const { return deferred[i] != 0; }
};
template <class Res, class Bridges>
struct PairedReplayStage {
  Bridges bridges;
  ReuseOptions rp;
  GBufferView g;
  const Res* reservoirs;
  PairedShift* shifts;
  PairedRound round;
  ReuseColor color;
  const uint32_t* list;
  RESTIR_HD void operator()(size_t i) const { paired_replay_slot(rp, g, reservoirs, shifts, bridges, round, list[i], color); }
};

// Pass 2: each pixel's reservoir combined with its partners' from the shifts of pass 1.
template <class Res, class Bridges>
struct PairedResampleStage {
  Bridges bridges;
  ReuseOptions rp;
  GBufferView g;
  const Res* reservoirs;
  const PairedShift* shifts;
  Res* next;
  PairedRound round;
  ReuseDebugView dbg;
  ReuseColor color;
  RESTIR_HD void operator()(int x, int y) const {
    paired_resample_pixel(rp, g, reservoirs, shifts, next, bridges, round, dbg, x, y, color);
  }
};

// RTXDI's boiling filter (biased; *.boiling_filter): pass 1, the mean unbiased contribution weight
// W of the reservoirs with W > 0 in each 16x16-pixel block, summed in pixel order (the same on
// every backend and thread count).
inline constexpr int kBoilingBlock = 16;
template <class Res>
struct BoilingMeanStage {
  const Res* reservoirs;
  float* block_mean;
  int width, height, blocks_x;
  RESTIR_HD void operator()(size_t b) const {
    const int x0 = int(b % size_t(blocks_x)) * kBoilingBlock, y0 = int(b / size_t(blocks_x)) * kBoilingBlock;
    float sum = 0;
    int count = 0;
    for (int y = y0; y < y0 + kBoilingBlock && y < height; ++y)
      for (int x = x0; x < x0 + kBoilingBlock && x < width; ++x) {
        const float w = reservoirs[size_t(y) * size_t(width) + size_t(x)].ucw;
        if (w > 0) sum += w, ++count;
      }
    block_mean[b] = count > 0 ? sum / float(count) : 0.0f;
  }
};

// Pass 2: a reservoir whose W exceeds `multiplier` x its block's mean is emptied. A sample that a
// rare candidate found and that spatiotemporal reuse then spreads over a region (a "boiling"
// blotch) has a W far above its neighbours'. RTXDI (RTXDI_BoilingFilter) compares W with the mean
// nonzero W of the thread group, multiplier = 10 / strength - 9. Dropping a sample removes its
// energy: the estimator is no longer unbiased (the bias is measured in README and `restir options`).
template <class Res>
struct BoilingDropStage {
  Res* reservoirs;
  const float* block_mean;
  int width, blocks_x;
  float multiplier;
  RESTIR_HD void operator()(int x, int y) const {
    Res& r = reservoirs[size_t(y) * size_t(width) + size_t(x)];
    const float mean = block_mean[size_t(y / kBoilingBlock) * size_t(blocks_x) + size_t(x / kBoilingBlock)];
    if (r.ucw > mean * multiplier) r = Res{};
  }
};

// Duplication maps (ReSTIR PT Enhanced, Lin, Kettunen, Wyman 2026, sec. 5; biased;
// *.duplication_map): pass 1, each pixel's sample identity (duplicate_key, 0 for none).
template <class Res>
struct DuplicateKeyStage {
  const Res* reservoirs;
  uint64_t* keys;
  RESTIR_HD void operator()(size_t i) const { keys[i] = reservoirs[i].has_sample() ? duplicate_key(reservoirs[i].sample) | 1u : 0; }
};

// Pass 2: D = the share of the other 288 pixels of the 17x17 window (those on screen count; the
// paper's denominator stays 288) holding the same sample, and next frame's M-cap at this pixel
// lerp(max_history, 1, D^0.1) (the paper's alpha = 0.1): spatiotemporal reuse that has copied one
// sample over a region is what makes ReSTIR's correlation blotches, so that region keeps less history.
inline constexpr int kDuplicationRadius = 8;
struct DuplicationCapStage {
  const uint64_t* keys;
  float* caps;
  int width, height;
  float max_history;  // rp.max_history, or kMaxConfidence for no cap
  RESTIR_HD void operator()(int x, int y) const {
    const uint64_t key = keys[size_t(y) * size_t(width) + size_t(x)];
    int same = 0;
    if (key != 0)
      for (int v = y - kDuplicationRadius; v <= y + kDuplicationRadius; ++v)
        for (int u = x - kDuplicationRadius; u <= x + kDuplicationRadius; ++u)
          if (v >= 0 && u >= 0 && v < height && u < width && (u != x || v != y) && keys[size_t(v) * size_t(width) + size_t(u)] == key)
            ++same;
    const float d = float(same) / 288.0f;
    const float t = d > 0 ? powf(d, 0.1f) : 0.0f;
    caps[size_t(y) * size_t(width) + size_t(x)] = max_history + (1.0f - max_history) * t;
  }
};

// A ReSTIR frame's initial candidates: out[p] = sample(surface, x, y, p) at every pixel.
template <class Res, class Sampler>
struct CandidateStage {
  Sampler sample;
  GBufferView g;
  Res* out;
  RESTIR_HD void operator()(int x, int y) const {
    const uint32_t p = uint32_t(y * g.width + x);
    out[p] = sample(g.at(x, y), x, y, p);
  }
};

// A ReSTIR frame's shading: shade(surface, reservoir, p) added to the pixel's sum, or the debug
// view's value (render.debug_view) instead.
template <class Res, class Shader>
struct ShadeStage {
  Shader shade;
  GBufferView g;
  const Res* reservoirs;
  DebugView view;
  ReuseDebugView dbg;
  Rgb* sum;
  RESTIR_HD void operator()(int x, int y) const {
    const uint32_t p = uint32_t(y * g.width + x);
    const Res& r = reservoirs[p];
    if (add_debug_view(view, r, dbg, p, sum, reconnection_depth_of(r))) return;
    sum[p] += shade(g.at(x, y), r, p);
  }
};

// The chains' average: a division (not a product by 1 / spp), for the rounding every backend shares.
struct AverageStage {
  Rgb* sum;
  float spp;
  RESTIR_HD void operator()(size_t i) const { sum[i] = sum[i] / spp; }
};

}  // namespace chain_detail

// One chain (pixel sample) of a ReSTIR integrator on backend B, with reservoirs of type Res.
template <class B, class Res>
struct ReservoirChain {
  using Exec = typename B::Exec;
  template <class T>
  using Array = typename Exec::template Array<T>;
  Array<GPacked> gbuffer, previous_gbuffer;
  Array<Rgb> emitted;     // this frame's emission toward the camera (GBufferView::emitted)
  Array<GMotion> motion;  // this frame's motion vectors, in a scene with animations
  Array<Res> reservoirs, previous;
  Array<Res> scratch;  // a reuse pass's output, swapped with reservoirs
  Array<uint8_t> source;
  Array<uint16_t> tried, rejected;
  // Paired spatial reuse: the pairing textures (built on the host, mirrored to the backend) and
  // each pixel's shifts to its partners (spatial_neighbors x pixels).
  PairingTextures pairing;
  Array<int16_t> pairing_offsets;
  Array<uint32_t> pairing_first;
  Array<int32_t> pairing_sizes;
  Array<PairingTransform> pairing_transforms;
  std::vector<PairingTransform> host_transforms;
  Array<PairedShift> paired_shifts;
  Array<uint8_t> paired_deferred;  // replay compaction: the pass-1 slots whose shift replays
  Array<uint32_t> replay_list;     // ... and their list (Exec::select)
  // render.reuse_rays = queued (ray_slots.h): the pass's recorded shadow rays, their answers, each
  // pixel's count and the list of recorded slots.
  Array<Ray> slot_rays;
  Array<uint8_t> slot_answers;
  Array<uint32_t> slot_counts, slot_list;
  bool queued_rays = false;
  Array<float> boiling_means;  // the boiling filter's per-block mean W
  Array<uint64_t> duplicate_keys;
  Array<float> history_caps;  // the duplication map's M-caps of this frame's pixels, read by the next frame's temporal pass
  bool has_history_caps = false;
  // RGB resampling weights (*.rgb_weights): the last spatial round's shading colour per pixel
  // (reuse_pixel.h's ReuseColor), and paired reuse's F per pass-1 shift.
  Array<Rgb> colors, shift_colors;
  bool has_colors = false;
  int width = 0, height = 0, previous_width = 0, previous_height = 0;
  bool has_history = false, has_motion = false;
  const MaterialParams* materials = nullptr;  // the backend's copy of the scene's (GBufferView::materials)
  Vec3 eye;                                   // this frame's camera position (GBufferView::eye)

  // What a frame starts from and a frame leaves for the next: the history. A copy lets A-SVGF
  // render the previous frame again from it (ReservoirFrame::rerender_previous).
  struct History {
    Array<Res> reservoirs;
    Array<GPacked> gbuffer;
    Array<float> caps;
    int width = 0, height = 0;
    bool valid = false, has_caps = false;
  };
  void copy_history_to(History& h) const {
    const size_t n = size_t(previous_width) * size_t(previous_height);
    h.width = previous_width, h.height = previous_height, h.valid = has_history, h.has_caps = has_history_caps;
    if (!has_history) return;
    Exec::copy(h.reservoirs, previous, n);
    Exec::copy(h.gbuffer, previous_gbuffer, n);
    if (has_history_caps) Exec::copy(h.caps, history_caps, n);
  }
  void swap_history(History& h) {
    previous.swap(h.reservoirs), previous_gbuffer.swap(h.gbuffer), history_caps.swap(h.caps);
    std::swap(previous_width, h.width), std::swap(previous_height, h.height);
    std::swap(has_history, h.valid), std::swap(has_history_caps, h.has_caps);
  }

  // Bytes of the chain's buffers (Integrator::buffer_bytes); a chain type with more adds its own.
  size_t bytes() const {
    return array_bytes(gbuffer) + array_bytes(previous_gbuffer) + array_bytes(emitted) + array_bytes(motion) + array_bytes(reservoirs) +
           array_bytes(previous) + array_bytes(scratch) + array_bytes(source) + array_bytes(tried) + array_bytes(rejected) +
           array_bytes(pairing_offsets) + array_bytes(pairing_first) + array_bytes(pairing_sizes) + array_bytes(pairing_transforms) +
           array_bytes(paired_shifts) + array_bytes(paired_deferred) + array_bytes(replay_list) + array_bytes(boiling_means) +
           array_bytes(duplicate_keys) + array_bytes(history_caps) + array_bytes(colors) + array_bytes(shift_colors) +
           array_bytes(slot_rays) + array_bytes(slot_answers) + array_bytes(slot_counts) + array_bytes(slot_list);
  }

  ReuseDebugView debug() { return {source.data, tried.data, rejected.data}; }
  GBufferView view() const { return {gbuffer.data, width, height, has_motion ? motion.data : nullptr, materials, emitted.data, eye}; }
  // The previous frame's surfaces, seen from its camera at previous_eye (its emission is not kept;
  // its materials are this frame's).
  GBufferView previous_view(Vec3 previous_eye) const {
    return {previous_gbuffer.data, width, height, nullptr, materials, nullptr, previous_eye};
  }

  // Primary hits of chain s, buffers sized for the frame (not cleared: every integrator's candidate
  // stage writes every pixel's reservoir before anything reads it), debug counters cleared.
  void begin_frame(const typename B::World& w, const RenderContext& ctx, const FrameInfo& frame, int s) {
    StageTimer timer(frame.stages, "primary");
    width = frame.camera->width(), height = frame.camera->height();
    const size_t n = size_t(width) * size_t(height);
    gbuffer.reserve(n), previous_gbuffer.reserve(n), emitted.reserve(n);
    reservoirs.reserve(n), previous.reserve(n), scratch.reserve(n);
    source.reserve(n), tried.reserve(n), rejected.reserve(n);
    Exec::zero(source, n), Exec::zero(tried, n), Exec::zero(rejected, n);
    has_motion = w.view().animation_count > 0;  // motion only where something can move
    if (has_motion) motion.reserve(n);
    queued_rays = ctx.options.render.reuse_rays == ReuseRays::queued;
    materials = w.view().world.scene.materials;
    eye = frame.camera->position();
    B::primary_hits(w, ctx, frame, s, gbuffer.data, emitted.data, has_motion ? motion.data : nullptr);
  }

  // Temporal reuse (when there is a compatible history), then the spatial rounds; bridges(surfaces,
  // n, temporal) makes a pixel's bridge (mis.h). planted: tests only (planted_bias.h).
  // rp.rgb_weights: the spatial rounds also write each pixel's shading colour (colors, has_colors).
  template <class Bridges>
  void reuse(const ReuseOptions& rp, const FrameInfo& frame, const Bridges& bridges, const ReuseFrame& frame_streams,
             const PlantedBias* planted = nullptr) {
    using namespace chain_detail;
    ReuseFrame f = frame_streams;
    f.planted_ratio_canonical = planted && planted->ratio_canonical_symmetric;
    has_colors = rp.rgb_weights && rp.spatial_neighbors > 0 && rp.spatial_rounds > 0;
    ReuseColor color;
    if (has_colors) {
      colors.reserve(size_t(width) * size_t(height));
      color.out = colors.data;
      color.planted_input_target = planted && planted->color_input_target;
    }
    if (rp.temporal && has_history && previous_width == width && previous_height == height) {
      StageTimer timer(frame.stages, "temporal");
      const PerspectiveCamera& previous_camera = frame.previous_camera ? *frame.previous_camera : *frame.camera;
      const TemporalStage<Res, Bridges> stage{bridges,         rp,
                                              view(),          previous_view(previous_camera.position()),
                                              previous_camera, reservoirs.data,
                                              previous.data,   scratch.data,
                                              f,               debug(),
                                              rp.duplication_map && has_history_caps ? history_caps.data : nullptr};
      run_pass(stage, bridges.fw.tracer, rp.temporal_mis, 2, "temporal reuse");
      reservoirs.swap(scratch);
    }
    {
      StageTimer timer(frame.stages, "spatial");
      if (rp.spatial_pairing == SpatialPairing::paired) {
        paired_rounds(rp, bridges, f, planted, color);
      } else {
        for (int round = 0; rp.spatial_neighbors > 0 && round < rp.spatial_rounds; ++round) {
          const SpatialStage<Res, Bridges> stage{bridges, rp, view(), reservoirs.data, scratch.data, f, round, debug(), color};
          run_pass(stage, bridges.fw.tracer, rp.spatial_mis, std::min(rp.spatial_neighbors, kMaxReuseNeighbors) + 1, "spatial reuse");
          reservoirs.swap(scratch);
        }
      }
    }
    if (rp.boiling_filter > 0) boiling_filter(rp.boiling_filter, frame);
    has_history_caps = rp.duplication_map;
    if (rp.duplication_map) duplication_map(rp, frame);
  }

  // A temporal or spatial pass over the pixels, combining up to `inputs` reservoirs a pixel with
  // `kind`: inline, or queued (ray_slots.h): the producer run, one any-hit query per recorded ray,
  // the consumer run.
  template <class Stage, class Tracer>
  void run_pass(const Stage& stage, const Tracer& tracer, restir::ReuseMis kind, int inputs, const char* what) {
    using namespace chain_detail;
    if (!queued_rays) return Exec::for_pixels(width, height, stage, what);
    const size_t pixels = size_t(width) * size_t(height);
    const uint32_t per_pixel = ray_slots_per_pixel(kind, inputs);
    slot_rays.reserve(pixels * per_pixel), slot_answers.reserve(pixels * per_pixel), slot_counts.reserve(pixels);
    const RaySlotsView slots{slot_rays.data, slot_answers.data, slot_counts.data, per_pixel};
    Exec::for_pixels(width, height, QueuedPassStage<Stage>{stage, slots, true}, "reuse: recording shadow rays");
    const uint32_t n = Exec::select(pixels * per_pixel, RecordedSlot{slots}, slot_list, "reuse: recorded rays");
    Exec::for_each(n, TraceSlotsStage<Tracer>{tracer, slots, slot_list.data}, "reuse: shadow rays");
    Exec::for_pixels(width, height, QueuedPassStage<Stage>{stage, slots, false}, what);
  }

  // The duplication map of this frame's final reservoirs, as the next frame's per-pixel M-caps.
  void duplication_map(const ReuseOptions& rp, const FrameInfo& frame) {
    using namespace chain_detail;
    StageTimer timer(frame.stages, "duplication_map");
    const size_t n = size_t(width) * size_t(height);
    duplicate_keys.reserve(n), history_caps.reserve(n);
    Exec::for_each(n, DuplicateKeyStage<Res>{reservoirs.data, duplicate_keys.data}, "duplication map: keys");
    const float cap = rp.max_history > 0 ? float(rp.max_history) : restir::kMaxConfidence;
    Exec::for_pixels(width, height, DuplicationCapStage{duplicate_keys.data, history_caps.data, width, height, cap}, "duplication map");
  }

  // RTXDI's boiling filter over this frame's final reservoirs (the ones shaded and kept as history).
  void boiling_filter(float strength, const FrameInfo& frame) {
    using namespace chain_detail;
    StageTimer timer(frame.stages, "boiling_filter");
    const int blocks_x = (width + kBoilingBlock - 1) / kBoilingBlock, blocks_y = (height + kBoilingBlock - 1) / kBoilingBlock;
    const size_t blocks = size_t(blocks_x) * size_t(blocks_y);
    boiling_means.reserve(blocks);
    Exec::for_each(blocks, BoilingMeanStage<Res>{reservoirs.data, boiling_means.data, width, height, blocks_x}, "boiling filter: means");
    const float multiplier = 10.0f / std::min(std::max(strength, 1e-6f), 1.0f) - 9.0f;
    Exec::for_pixels(width, height, BoilingDropStage<Res>{reservoirs.data, boiling_means.data, width, blocks_x, multiplier},
                     "boiling filter");
  }

  // The spatial rounds of paired reuse (paired_reuse.h): per round, the shift pass, then the
  // resampling pass.
  template <class Bridges>
  void paired_rounds(const ReuseOptions& rp, const Bridges& bridges, const ReuseFrame& f, const PlantedBias* planted, ReuseColor color) {
    using namespace chain_detail;
    const int k = std::min(rp.spatial_neighbors, PairingView::kMaxTextures);
    if (k <= 0 || rp.spatial_rounds <= 0) return;
    if (color.out) {
      shift_colors.reserve(size_t(k) * size_t(width) * size_t(height));
      color.shifts = shift_colors.data;
    }
    pairing.prepare(k, rp.spatial_radius);
    const PairingView view{Exec::mirror(pairing_offsets, pairing.offsets().data(), pairing.offsets().size()),
                           Exec::mirror(pairing_first, pairing.first().data(), pairing.first().size()),
                           Exec::mirror(pairing_sizes, pairing.sizes().data(), pairing.sizes().size()), k};
    const size_t slots = size_t(k) * size_t(width) * size_t(height);
    paired_shifts.reserve(slots);
    // Replay compaction: bridges whose shifts may replay say whether the frame asked for it.
    bool compact = false;
    if constexpr (requires { bridges.compact_replays(); }) compact = bridges.compact_replays();
    if (compact) paired_deferred.reserve(slots);
    for (int round = 0; round < rp.spatial_rounds; ++round) {
      host_transforms.resize(size_t(k));
      for (int t = 0; t < k; ++t) host_transforms[size_t(t)] = PairingView::transform(t, pairing.sizes()[size_t(t)], f.frame, f.seed, f.chain, round);
      const PairingTransform* transforms = Exec::mirror(pairing_transforms, host_transforms.data(), host_transforms.size());
      const PairedRound pr{view, transforms, f, round, planted && planted->pairing_one_sided, planted && planted->pairing_broken};
      Exec::for_pixels(width, height,
                       PairedShiftStage<Res, Bridges>{bridges, rp, this->view(), reservoirs.data, paired_shifts.data, pr, color,
                                                      compact ? paired_deferred.data : nullptr},
                       "paired reuse: shifts");
      if (compact) {
        const uint32_t replays = Exec::select(slots, DeferredSlot{paired_deferred.data}, replay_list, "paired reuse: replay list");
        Exec::for_each(replays,
                       PairedReplayStage<Res, Bridges>{bridges, rp, this->view(), reservoirs.data, paired_shifts.data, pr, color,
                                                       replay_list.data},
                       "paired reuse: replayed shifts");
      }
      Exec::for_pixels(width, height,
                       PairedResampleStage<Res, Bridges>{bridges, rp, this->view(), reservoirs.data, paired_shifts.data, scratch.data, pr,
                                                         debug(), color},
                       "paired reuse: resampling");
      reservoirs.swap(scratch);
    }
  }

  // This frame's reservoirs and surfaces are the next frame's history.
  void end_frame() {
    previous.swap(reservoirs);
    previous_gbuffer.swap(gbuffer);
    previous_width = width, previous_height = height;
    has_history = true;
  }
};

// `spp` chains (made on first use) rendered in order by render_chain(s, chain), each adding its
// radiance to sum, then averaged into `out`.
template <class Exec, class Chain, class RenderChain>
void render_chains(std::vector<std::unique_ptr<Chain>>& chains, int spp, typename Exec::template Array<Rgb>& sum, Image& out,
                   const RenderChain& render_chain) {
  if (int(chains.size()) != spp) {
    chains.clear();
    for (int s = 0; s < spp; ++s) chains.push_back(std::make_unique<Chain>());
  }
  const size_t pixels = out.size();
  sum.reserve(pixels);
  Exec::zero(sum, pixels);
  for (int s = 0; s < spp; ++s) render_chain(s, *chains[size_t(s)]);
  Exec::for_each(pixels, chain_detail::AverageStage{sum.data, float(spp)}, "averaging the chains");
  Exec::download(out.pixels.data(), sum, pixels);
}

// A ReSTIR integrator's frame on backend B: `spp` chains (Chain derives from ReservoirChain), each
// rendered by the algorithm's render_chain -- primary hits, its candidates, reuse, its shading --
// and averaged. Virtual dispatch once per chain and frame, never per pixel.
template <class B, class Chain>
class ReservoirFrame : public Integrator {
 public:
  using Exec = typename B::Exec;
  using Tracer = typename B::Tracer;
  explicit ReservoirFrame(const RenderContext& ctx) : ctx_(ctx) {}

  void render_frame(const FrameInfo& frame, Image& out) override {
    if (keep_history_) {  // the history this frame starts from, kept for the next frame's rerender_previous
      std::swap(started_previous_, started_current_);
      started_current_.resize(chains_.size());
      for (size_t s = 0; s < chains_.size(); ++s) {
        if (!started_current_[s]) started_current_[s] = std::make_unique<History>();
        chains_[s]->copy_history_to(*started_current_[s]);
      }
    }
    render_chains_of(frame, out);
    sum_is_frame_ = true;
  }

  // A-SVGF: frame f-1 rendered again, in frame f's scene, from the copy of the history it started
  // from (none for frame 0, or for a chain made in frame f-1), with its own random numbers (its
  // FrameInfo's index): where the scene did not change, the same image bit for bit. The chains'
  // history is exchanged with the copy and back, so frame f+1 starts from frame f's history.
  bool rerenders_previous() const override { return true; }
  void keep_history(bool on) override { keep_history_ = on; }
  FrameBuffer frame_buffer() const override { return frame_buffer_of<Exec>(sum_, sum_is_frame_); }
  size_t buffer_bytes() const override {
    size_t b = array_bytes(sum_);
    for (const auto& c : chains_) b += c->bytes();
    for (const auto* kept : {&started_previous_, &started_current_})
      for (const auto& h : *kept)
        if (h) b += array_bytes(h->reservoirs) + array_bytes(h->gbuffer) + array_bytes(h->caps);
    return b;
  }
  void rerender_previous(const FrameInfo& previous, Image& out) override {
    started_previous_.resize(chains_.size());
    for (auto& h : started_previous_)
      if (!h) h = std::make_unique<History>();
    const auto exchange = [&] {
      for (size_t s = 0; s < chains_.size(); ++s) chains_[s]->swap_history(*started_previous_[s]);
    };
    exchange();
    render_chains_of(previous, out);
    exchange();
    sum_is_frame_ = false;  // sum_ holds the previous frame again, not the frame shown
  }

 protected:
  using History = typename Chain::History;

  void render_chains_of(const FrameInfo& frame, Image& out) {
    const RayCountScope counting(frame.stages, [this] { return world_.ray_totals(); });
    world_.update(ctx_, frame);
    render_chains<Exec>(chains_, ctx_.options.render.spp, sum_, out, [&](int s, Chain& c) {
      c.begin_frame(world_, ctx_, frame, s);
      render_chain(frame, ReuseFrame{uint32_t(frame.index), ctx_.options.render.seed, uint32_t(s)}, c);
      c.end_frame();
    });
  }

  // Chain c's candidates, reuse and shading, between its primary hits and its end of frame; f:
  // the random streams of its chain (f.chain) in this frame.
  virtual void render_chain(const FrameInfo& frame, const ReuseFrame& f, Chain& c) = 0;

  // The initial candidates of chain c (the stage "candidates"): sample(surface, x, y, p).
  template <class Res, class Sampler>
  void candidates(const FrameInfo& frame, Chain& c, const Sampler& sample, const char* what) {
    StageTimer timer(frame.stages, "candidates");
    Exec::for_pixels(c.width, c.height, chain_detail::CandidateStage<Res, Sampler>{sample, c.view(), c.reservoirs.data}, what,
                     frame.progress);
  }
  // Chain c's radiance added to the frame's sum (the stage "shading"): shade(surface, reservoir, p).
  template <class Res, class Shader>
  void shade(const FrameInfo& frame, Chain& c, const Shader& shader, const char* what) {
    StageTimer timer(frame.stages, "shading");
    const chain_detail::ShadeStage<Res, Shader> stage{shader, c.view(), c.reservoirs.data, ctx_.options.render.debug_view, c.debug(),
                                                      sum_.data};
    Exec::for_pixels(c.width, c.height, stage, what);
  }
  const FrameWorld<Tracer>& fw() const { return world_.view(); }

  RenderContext ctx_;
  typename B::World world_;
  std::vector<std::unique_ptr<Chain>> chains_;
  typename Exec::template Array<Rgb> sum_;
  // A-SVGF (keep_history): per chain, the history frame f-1 started from and the one frame f did.
  bool keep_history_ = false;
  std::vector<std::unique_ptr<History>> started_previous_, started_current_;
  bool sum_is_frame_ = false;  // sum_ holds the last frame rendered (not a rerendered previous one)
};

}  // namespace rl
