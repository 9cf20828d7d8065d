// The reference path tracer's frame, written once for every backend (cpu_backend.h): a wavefront
// (issue 9; pbrt-v4's wavefront integrator). Paths advance bounce by bounce in waves of
// Exec::kWaveItems (pixel, sample) paths, each stage a loop over flat buffers -- camera rays; then
// per bounce: the live paths' rays queued and traced (closest hits, no shading), shading
// (path_bounce), the shadow rays queued and traced (any hit), their contributions added by owner,
// and the live paths compacted -- then each pixel's samples summed in order. Each path keeps its
// own random stream and runs path_bounce, so the image equals path_radiance's
// (tests/integrators/path/test_path_tracer.cpp) whatever the thread count or the schedule.
#pragma once
#include <algorithm>
#include <vector>

#include "frame/integrator.h"
#include "integrators/path/path_pixel.h"

namespace rl {

namespace path_frame_detail {

inline constexpr size_t kChunk = 256;  // paths per host task

struct StartStage {
  CameraSampling cs;
  PerspectiveCamera camera;
  int frame, width;
  uint32_t spp;
  size_t begin;  // the wave's first (pixel, sample) index
  PathState* paths;
  uint32_t* live;
  RESTIR_HD void operator()(size_t a, size_t b) const {
#ifdef __CUDA_ARCH__
    for (size_t i = a; i < b; ++i) start_path(cs, camera, frame, width, spp, begin, paths, live, i);
#else
    start_path_range(cs, camera, frame, width, spp, begin, paths, live, a, b);
#endif
  }
};

struct GatherRays {
  const PathState* paths;
  const uint32_t* live;
  Ray* rays;
  RESTIR_HD void operator()(size_t a, size_t b) const {
    for (size_t k = a; k < b; ++k) rays[k] = paths[live[k]].ray;
  }
};

struct ShadeStage {
  PathWorld world;
  PathOptions po;
  PathState* paths;
  const uint32_t* live;
  const Hit* hits;
  PendingShadow* shadows;
  uint8_t* alive;
  RESTIR_HD void operator()(size_t a, size_t b) const {
#ifdef __CUDA_ARCH__
    for (size_t k = a; k < b; ++k) alive[k] = path_bounce(world, po, paths[live[k]], hits[k].valid() ? &hits[k] : nullptr, shadows[k]);
#else
    shade_paths(world, po, paths, live, hits, shadows, alive, a, b);
#endif
  }
};

struct HasShadow {
  const PendingShadow* shadows;
  RESTIR_HD bool operator()(size_t k) const { return shadows[k].valid; }
};
struct IsAlive {
  const uint8_t* alive;
  RESTIR_HD bool operator()(size_t k) const { return alive[k] != 0; }
};

struct GatherShadowRays {
  const PendingShadow* shadows;
  const uint32_t* owner;
  Ray* rays;
  RESTIR_HD void operator()(size_t a, size_t b) const {
    for (size_t j = a; j < b; ++j) rays[j] = shadows[owner[j]].ray;
  }
};

// One shadow ray per path and bounce: no two items touch one path.
struct AddUnblocked {
  PathState* paths;
  const uint32_t* live;
  const PendingShadow* shadows;
  const uint32_t* owner;
  const uint8_t* blocked;
  RESTIR_HD void operator()(size_t a, size_t b) const {
    for (size_t j = a; j < b; ++j)
      if (!blocked[j]) paths[live[owner[j]]].L += shadows[owner[j]].contribution;
  }
};

struct CompactLive {
  const uint32_t* live;
  const uint32_t* kept;
  uint32_t* next;
  RESTIR_HD void operator()(size_t a, size_t b) const {
    for (size_t j = a; j < b; ++j) next[j] = live[kept[j]];
  }
};

// Pixel sums in path order (a pixel's samples in order): the same floats whatever the schedule.
struct Accumulate {
  const PathState* paths;
  size_t begin, n, spp, first_pixel;
  Rgb* sums;
  RESTIR_HD void operator()(size_t i) const {
    const size_t pixel = first_pixel + i;
    const size_t a = pixel * spp > begin ? pixel * spp : begin, b = (pixel + 1) * spp < begin + n ? (pixel + 1) * spp : begin + n;
    Rgb s = sums[pixel];
    for (size_t k = a; k < b; ++k) s += paths[k - begin].L;
    sums[pixel] = s;
  }
};

struct Average {
  Rgb* sums;
  float spp;
  RESTIR_HD void operator()(size_t i) const { sums[i] = sums[i] / spp; }
};

}  // namespace path_frame_detail

template <class B>
class PathFrame final : public Integrator {
 public:
  using Exec = typename B::Exec;
  explicit PathFrame(const RenderContext& ctx) : ctx_(ctx) {}
  bool rerenders_previous() const override { return true; }  // every frame a function of its FrameInfo alone
  FrameBuffer frame_buffer() const override { return frame_buffer_of<Exec>(sums_, sums_is_frame_); }
  // A-SVGF: the previous frame again (into sums_, which then no longer holds the frame shown).
  void rerender_previous(const FrameInfo& previous, Image& out) override {
    render_frame(previous, out);
    sums_is_frame_ = false;
  }
  size_t buffer_bytes() const override {
    return array_bytes(paths_) + array_bytes(live_) + array_bytes(next_live_) + array_bytes(rays_) + array_bytes(hits_) +
           array_bytes(shadows_) + array_bytes(alive_) + array_bytes(blocked_) + array_bytes(owner_) + array_bytes(kept_) +
           array_bytes(sums_);
  }

  void render_frame(const FrameInfo& frame, Image& out) override {
    using namespace path_frame_detail;
    const RayCountScope counting(frame.stages, [this] { return world_.ray_totals(); });
    world_.update(ctx_, frame);
    const size_t spp = size_t(ctx_.options.render.spp), pixels = out.size(), total = pixels * spp;
    const size_t wave = std::min(total, Exec::kWaveItems), waves = (total + Exec::kWaveItems - 1) / Exec::kWaveItems;
    reserve(wave, pixels);
    Exec::zero(sums_, pixels);
    for (size_t w = 0; w < waves; ++w) {
      const size_t begin = w * Exec::kWaveItems, n = std::min(Exec::kWaveItems, total - begin);
      start_paths(frame, out.width, begin, n);
      bool primary = true;
      for (size_t live = n; live > 0; primary = false) live = trace_bounce(frame, live, primary);
      StageTimer timer(frame.stages, "film");
      const size_t first = begin / spp, last = (begin + n - 1) / spp;
      Exec::for_each(last - first + 1, Accumulate{paths_.data, begin, n, spp, first, sums_.data}, "summing the pixels' samples");
      if (frame.progress) frame.progress(int(w + 1), int(waves));
    }
    // The mean (the same IEEE division on every backend); non-finite values: the driver reports them.
    StageTimer timer(frame.stages, "film");
    Exec::for_each(pixels, Average{sums_.data, float(spp)}, "averaging the pixels' samples");
    Exec::download(out.pixels.data(), sums_, pixels);
    sums_is_frame_ = true;
  }

 private:
  void reserve(size_t wave, size_t pixels) {
    paths_.reserve(wave), live_.reserve(wave), next_live_.reserve(wave), rays_.reserve(wave), hits_.reserve(wave);
    shadows_.reserve(wave), alive_.reserve(wave), owner_.reserve(wave), kept_.reserve(wave), blocked_.reserve(wave);
    sums_.reserve(pixels);
  }

  void start_paths(const FrameInfo& frame, int width, size_t begin, size_t n) {
    StageTimer timer(frame.stages, "camera");
    const path_frame_detail::StartStage stage{camera_sampling(ctx_.options), *frame.camera, frame.index, width,
                                              uint32_t(ctx_.options.render.spp), begin, paths_.data, live_.data};
    Exec::for_chunks(n, path_frame_detail::kChunk, stage, "camera rays");
  }

  // One bounce of the `live` paths listed in live_: closest hits, shading, shadow rays,
  // compaction. Returns how many paths go on (listed in live_ again).
  size_t trace_bounce(const FrameInfo& frame, size_t live, bool primary) {
    using namespace path_frame_detail;
    {
      StageTimer timer(frame.stages, "intersect");
      Exec::for_chunks(live, kChunk, GatherRays{paths_.data, live_.data, rays_.data}, "queueing rays");
      B::trace_closest(world_, rays_.data, hits_.data, live, primary);
    }
    {
      StageTimer timer(frame.stages, "shade");
      const ShadeStage stage{world_.view().world, ctx_.options.path, paths_.data, live_.data, hits_.data, shadows_.data, alive_.data};
      Exec::for_chunks(live, kChunk, stage, "shading");
    }
    {
      StageTimer timer(frame.stages, "shadow");
      const uint32_t m = Exec::select(live, HasShadow{shadows_.data}, owner_, "queueing shadow rays");
      Exec::for_chunks(m, kChunk, GatherShadowRays{shadows_.data, owner_.data, rays_.data}, "queueing shadow rays");
      B::trace_any(world_, rays_.data, blocked_.data, m);
      Exec::for_chunks(m, kChunk, AddUnblocked{paths_.data, live_.data, shadows_.data, owner_.data, blocked_.data}, "next-event estimates");
    }
    const uint32_t kept = Exec::select(live, IsAlive{alive_.data}, kept_, "compacting the paths");
    Exec::for_chunks(kept, kChunk, CompactLive{live_.data, kept_.data, next_live_.data}, "compacting the paths");
    live_.swap(next_live_);
    return kept;
  }

  RenderContext ctx_;
  typename B::World world_;
  // The wavefront's buffers, allocated once and reused by every wave and frame.
  template <class T>
  using Array = typename Exec::template Array<T>;
  Array<PathState> paths_;
  Array<uint32_t> live_, next_live_;  // indices into paths_ of the paths still being traced, in order
  Array<Ray> rays_;                   // the bounce's closest-hit queue, then its shadow-ray queue
  Array<Hit> hits_;
  Array<PendingShadow> shadows_;
  Array<uint8_t> alive_, blocked_;
  Array<uint32_t> owner_, kept_;  // the shadow queue's owners (live slots), the surviving live slots
  Array<Rgb> sums_;
  bool sums_is_frame_ = false;  // sums_ holds the last frame rendered (not a rerendered previous one)
};

}  // namespace rl
