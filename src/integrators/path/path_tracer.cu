// The path tracer's wavefront on the GPU (pt_cuda.h). Every per-path function is the CPU's own
// (path_kernel.h, bvh_traverse.h); this file only moves data and launches the stages.
#include <cuda_runtime.h>

#include <algorithm>
#include <chrono>

#include "backends/bvh.h"
#include "backends/bvh_traverse.h"
#include "backends/cuda/device_store.cuh"
#include "backends/view_upload.h"
#include "integrators/path/path_pixel.h"
#include "integrators/path/path_tracer.h"
#include "integrators/path/path_tracer_cuda.h"

namespace rl {

namespace {

using cuda::check;
using cuda::DeviceArray;
using cuda::DeviceStore;

constexpr uint32_t kBlock = 128;
inline uint32_t blocks_for(size_t n) { return uint32_t((n + kBlock - 1) / kBlock); }

// ---------------------------------------------------------------- the stages

struct WaveArgs {
  PerspectiveCamera camera;
  CameraSampling sampling;
  int frame = 0;
  uint64_t begin = 0;  // first (pixel, sample) index of the wave
  uint32_t spp = 1;
  uint32_t width = 1;
};

__global__ void start_paths_kernel(WaveArgs a, PathState* paths, uint32_t* live, uint32_t n) {
  const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  const uint64_t index = a.begin + i;
  const uint32_t pixel = uint32_t(index / a.spp), s = uint32_t(index % a.spp);
  const int x = int(pixel % a.width), y = int(pixel / a.width);
  PathState st;
  st.ray = camera_ray(a.sampling, a.camera, x, y, a.frame, int(s));
  st.rng = make_rng(pixel, uint32_t(a.frame), RngPass::path, a.sampling.seed, s);
  paths[i] = st;
  live[i] = i;
}

__global__ void intersect_kernel(BvhView bvh, const PathState* paths, const uint32_t* live, uint32_t n, Hit* hits) {
  const uint32_t k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= n) return;
  Hit h;
  bvh_trace(bvh, paths[live[k]].ray, false, &h);
  hits[k] = h;
}

__global__ void shade_kernel(PathWorld world, PathOptions opt, PathState* paths, const uint32_t* live, uint32_t n, const Hit* hits,
                             PendingShadow* shadows, uint8_t* alive) {
  const uint32_t k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= n) return;
  const Hit h = hits[k];
  PendingShadow sh;
  alive[k] = path_bounce(world, opt, paths[live[k]], h.valid() ? &h : nullptr, sh) ? 1 : 0;
  shadows[k] = sh;
}

// Shadow rays, then the live paths compacted into next_live. The order of next_live depends on
// the schedule, but each path keeps its own state and random stream, so the image does not.
__global__ void shadow_compact_kernel(BvhView bvh, PathState* paths, const uint32_t* live, uint32_t n, const PendingShadow* shadows,
                                      const uint8_t* alive, uint32_t* next_live, uint32_t* next_count) {
  const uint32_t k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= n) return;
  const PendingShadow& sh = shadows[k];
  PathState& st = paths[live[k]];
  if (sh.valid && !bvh_trace(bvh, sh.ray, true, nullptr)) st.L += sh.contribution;
  if (alive[k]) next_live[atomicAdd(next_count, 1u)] = live[k];
}

// Pixel sums in path order (a pixel's samples in order, as the CPU adds them).
__global__ void accumulate_kernel(const PathState* paths, uint64_t begin, uint32_t n, uint32_t spp, Rgb* sums) {
  const uint64_t first_pixel = begin / spp, last_pixel = (begin + n - 1) / spp;
  const uint64_t pixel = first_pixel + blockIdx.x * blockDim.x + threadIdx.x;
  if (pixel > last_pixel) return;
  const uint64_t a = std::max(begin, pixel * spp), b = std::min(begin + n, (pixel + 1) * spp);
  Rgb s = sums[pixel];
  for (uint64_t i = a; i < b; ++i) s += paths[i - begin].L;
  sums[pixel] = s;
}

__global__ void average_kernel(Rgb* sums, size_t n, float spp) {
  const size_t i = size_t(blockIdx.x) * blockDim.x + threadIdx.x;
  if (i < n) sums[i] = sums[i] / spp;
}

// Each stage's device time from CUDA events on the default stream, read once at the end of the
// frame: the stages run back to back, and the host waits only where it must (each bounce's live
// count). A host-side timer around every launch would need a sync per launch, which at a path
// depth of 65 cost more than the kernels (up to ~500 syncs a frame).
class EventStages {
 public:
  ~EventStages() {
    for (cudaEvent_t e : events_) cudaEventDestroy(e);
  }
  // Time what `launch` enqueues as `stage`.
  template <class F>
  void run(const char* stage, const F& launch) {
    cudaEvent_t a = next(), b = next();
    check(cudaEventRecord(a), "timing a stage");
    launch();
    check(cudaGetLastError(), stage);
    check(cudaEventRecord(b), "timing a stage");
    marks_.push_back({stage, a, b});
  }
  // Forgets what a frame that threw left behind.
  void reset() { marks_.clear(), used_ = 0; }
  // Waits for the device and adds each stage's time to `times` (which may be null).
  void flush(StageTimes* times) {
    if (!marks_.empty()) check(cudaEventSynchronize(marks_.back().stop), "finishing the frame");
    for (const Mark& m : marks_) {
      float ms = 0;
      check(cudaEventElapsedTime(&ms, m.start, m.stop), "timing a stage");
      if (times) times->add(m.stage, double(ms));
    }
    marks_.clear();
    used_ = 0;
  }

 private:
  struct Mark {
    const char* stage;
    cudaEvent_t start, stop;
  };
  cudaEvent_t next() {
    if (used_ == events_.size()) {
      cudaEvent_t e;
      check(cudaEventCreate(&e), "creating an event");
      events_.push_back(e);
    }
    return events_[used_++];
  }
  std::vector<cudaEvent_t> events_;
  size_t used_ = 0;
  std::vector<Mark> marks_;
};

class CudaPathTracer final : public Integrator {
 public:
  explicit CudaPathTracer(const RenderContext& ctx) : ctx_(ctx) {
    check(cudaSetDevice(0), "selecting device 0");
    upload_world();
  }

  void render_frame(const FrameInfo& frame, Image& out) override {
    // The scene (and with it its lights) moved since it was copied -- the next frame of an animated
    // scene, or frame 0 again after FrameRenderer::reset: copy it again.
    if (ctx_.accel.generation() != uploaded_generation_) {
      StageTimer timer(frame.stages, "upload");
      upload_world();
    }
    const Options& o = ctx_.options;
    stages_.reset();
    const size_t spp = size_t(o.render.spp), pixels = out.size(), total = pixels * spp;
    const size_t wave = std::min(total, kWave);
    paths_.reserve(wave), live_.reserve(wave), next_live_.reserve(wave), hits_.reserve(wave), shadows_.reserve(wave);
    alive_.reserve(wave), sums_.reserve(pixels), count_.reserve(1);
    check(cudaMemset(sums_.data, 0, pixels * sizeof(Rgb)), "clearing the film");
    WaveArgs args{*frame.camera, camera_sampling(o), frame.index, 0, uint32_t(spp), uint32_t(out.width)};
    for (size_t begin = 0; begin < total; begin += kWave) {
      const uint32_t n = uint32_t(std::min(kWave, total - begin));
      args.begin = begin;
      stages_.run("camera", [&] { start_paths_kernel<<<blocks_for(n), kBlock>>>(args, paths_.data, live_.data, n); });
      for (uint32_t live = n; live > 0;) live = trace_bounce(live);
      stages_.run("film", [&] {
        accumulate_kernel<<<blocks_for(size_t(n) / spp + 2), kBlock>>>(paths_.data, begin, n, uint32_t(spp), sums_.data);
      });
      if (frame.progress) frame.progress(int(begin / kWave + 1), int((total + kWave - 1) / kWave));
    }
    // The mean on the device (the same IEEE division as the CPU's), then one copy to the host.
    stages_.run("film", [&] { average_kernel<<<blocks_for(pixels), kBlock>>>(sums_.data, pixels, float(spp)); });
    stages_.flush(frame.stages);
    StageTimer timer(frame.stages, "download");
    // (Non-finite pixels are reported by FrameRenderer, as for every integrator.)
    check(cudaMemcpy(out.pixels.data(), sums_.data, pixels * sizeof(Rgb), cudaMemcpyDeviceToHost), "copying the image back");
  }

 private:
  // Paths in flight: a 1920x1080 frame at 1 spp in one wave, so that each bounce is one launch of
  // each stage (2^22 paths take 0.7 GB: 173 bytes of path state, hit, shadow ray and lists each).
  static constexpr size_t kWave = size_t(1) << 22;

  // One bounce of the `live` paths listed in live_; returns how many go on (listed in live_ again).
  // The three launches queue behind each other; reading the live count is the bounce's one wait.
  uint32_t trace_bounce(uint32_t live) {
    stages_.run("intersect", [&] { intersect_kernel<<<blocks_for(live), kBlock>>>(bvh_, paths_.data, live_.data, live, hits_.data); });
    stages_.run("shade", [&] {
      shade_kernel<<<blocks_for(live), kBlock>>>(world_, ctx_.options.path, paths_.data, live_.data, live, hits_.data, shadows_.data,
                                                 alive_.data);
    });
    stages_.run("shadow", [&] {
      check(cudaMemsetAsync(count_.data, 0, sizeof(uint32_t)), "clearing a counter");
      shadow_compact_kernel<<<blocks_for(live), kBlock>>>(bvh_, paths_.data, live_.data, live, shadows_.data, alive_.data,
                                                          next_live_.data, count_.data);
    });
    uint32_t next = 0;
    check(cudaMemcpy(&next, count_.data, sizeof(uint32_t), cudaMemcpyDeviceToHost), "tracing a bounce (closest hits, shading, shadow rays)");
    std::swap(live_.data, next_live_.data);
    std::swap(live_.capacity, next_live_.capacity);
    return next;
  }

  // The scene, lights and BVH as they are now, copied to the device.
  void upload_world() {
    store_.clear();
    uploaded_generation_ = ctx_.accel.generation();
    bvh_ = cuda::upload_bvh(store_, build_bvh(ctx_.scene));
    world_.scene = store_scene_view(store_, ctx_.accel.scene_view());
    world_.lights = store_lights_view(store_, ctx_.lights.view());
    world_.ray_epsilon = ctx_.accel.ray_epsilon();
  }

  RenderContext ctx_;
  uint64_t uploaded_generation_ = 0;
  DeviceStore store_;
  BvhView bvh_;
  PathWorld world_;
  DeviceArray<PathState> paths_;
  DeviceArray<uint32_t> live_, next_live_, count_;
  DeviceArray<Hit> hits_;
  DeviceArray<PendingShadow> shadows_;
  DeviceArray<uint8_t> alive_;
  DeviceArray<Rgb> sums_;
  EventStages stages_;
};

}  // namespace

std::unique_ptr<Integrator> make_cuda_path_tracer(const RenderContext& ctx) { return std::make_unique<CudaPathTracer>(ctx); }

}  // namespace rl
