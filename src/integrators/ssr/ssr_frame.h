// Screen-space reflections (issue 12): the reflections real-time engines ship, as the cheap and
// biased baseline that the thesis compares ReSTIR PT against -- written once for every backend
// (cpu_backend.h; issue 48: ssr on the GPU). Per pixel sample:
//   1. the G-buffer (primary hits: camera rays traced as one queue) and its Hi-Z pyramid, and the
//      lit colour of every pixel: its emission plus direct lighting, the path tracer at depth 1
//      continuing the G-buffer's hits with path_radiance's random numbers (one light sample and one
//      BSDF sample, MIS) -- what the frame shows before reflections;
//   2. surfaces whose roughness is at most ssr.roughness_cutoff take their reflected light from
//      the screen instead: ssr.rays directions drawn from the BSDF, each marched through the depth
//      buffer (ssr_march.h) and weighted f |cos| / pdf; a hit returns the lit colour of the pixel
//      it lands on, a miss the environment (ssr.fallback = environment) or nothing;
//   3. the resolve (Stachowiak 2015): a glossy pixel also reuses the rays its neighbours traced, a
//      ratio estimator -- much less noise, slightly biased, as in the engines (ssr_pixel.h);
//   4. optionally (ssr.temporal), the reflective pixels blend with the previous frame's, reprojected.
// What it cannot show, by design (README "Screen-space reflections"): objects off screen or hidden
// from the camera, reflections of reflections (a mirror seen in a mirror shows its own lit colour),
// light arriving at glossy surfaces from emitters off screen, glass transmission (the transmitted
// direction returns the fallback), and view-dependent colour of the surface a ray lands on. A
// smooth-coated diffuse surface counts as rough (bsdf_roughness: its non-delta lobe is the base),
// so its coat mirrors emitters (the lit colour's BSDF sample) but not the screen.
#pragma once
#include <algorithm>

#include "frame/integrator.h"
#include "frame/pixel_sampler.h"
#include "integrators/path/path_pixel.h"
#include "integrators/ssr/ssr_pixel.h"

namespace rl {

namespace ssr_frame_detail {

struct CameraRayStage {
  CameraSampling cs;
  PerspectiveCamera camera;
  int frame, sample;
  Ray* rays;
  RESTIR_HD void operator()(int x, int y) const {
    rays[size_t(y) * size_t(camera.width()) + size_t(x)] = camera_ray(cs, camera, x, y, frame, sample);
  }
};

struct GBufferStage {
  PathWorld w;
  const Ray* rays;
  const Hit* hits;
  GPacked* g;
  Rgb* emitted;
  GMotion* motion;  // null: the scene has no animations
  const Mat4* back;
  uint32_t back_count;
  int width;
  RESTIR_HD void operator()(int x, int y) const {
    const size_t i = size_t(y) * size_t(width) + size_t(x);
    fill_gpacked(w.scene, w.lights, rays[i], hits[i].valid() ? &hits[i] : nullptr, g[i], emitted[i], back, back_count,
                 motion ? motion + i : nullptr);
  }
};

struct HiZBaseStage {
  const GPacked* g;
  Vec3 position, forward;
  float* z;
  int width;
  RESTIR_HD void operator()(int x, int y) const {
    const size_t i = size_t(y) * size_t(width) + size_t(x);
    z[i] = hiz_depth(g[i], position, forward);
  }
};

struct HiZReduceStage {
  HiZView hiz;
  int level;
  float* z;  // the level's values
  RESTIR_HD void operator()(int x, int y) const { z[size_t(y) * size_t(hiz.layout.width[level]) + size_t(x)] = hiz_reduce(hiz, level, x, y); }
};

template <class Tracer>
struct DirectStage {
  PathWorld w;
  Tracer tracer;
  PathOptions depth1;
  const Ray* rays;
  const Hit* hits;
  Rgb* lit;
  int width;
  uint32_t frame, sample;
  uint64_t seed;
  RESTIR_HD void operator()(int x, int y) const {
    const uint32_t p = uint32_t(y * width + x);
    Pcg32 rng = make_rng(p, frame, RngPass::path, seed, sample);
    const Hit none;  // invalid: the camera ray escaped
    lit[p] = path_radiance(w, tracer, depth1, rays[p], rng, false, hits[p].valid() ? &hits[p] : &none);
  }
};

struct ReflectionStage {
  SsrPixelView v;
  ReflectionRay* out;
  uint32_t frame, sample;
  uint64_t seed;
  RESTIR_HD void operator()(int x, int y) const {
    const uint32_t p = uint32_t(y * v.g.width + x);
    const size_t rays = size_t(v.so.rays);
    const GSurface sf = v.g.surface(p);
    if (!v.reflective(sf)) {
      for (size_t i = 0; i < rays; ++i) out[p * rays + i] = ReflectionRay{};
      return;
    }
    Pcg32 rng = make_rng(p, frame, RngPass::misc, seed, sample);
    for (size_t i = 0; i < rays; ++i) out[p * rays + i] = trace_reflection(v, sf, rng);
  }
};

struct ResolveStage {
  SsrPixelView v;
  Rgb* sum;
  uint32_t frame, sample;
  uint64_t seed;
  RESTIR_HD void operator()(int x, int y) const {
    const uint32_t p = uint32_t(y * v.g.width + x);
    const GSurface sf = v.g.surface(p);
    if (!v.reflective(sf)) {
      sum[p] += v.lit[p];
      return;
    }
    Pcg32 rng = make_rng(p, frame, RngPass::spatial, seed, sample);
    sum[p] += sf.le + reflected(v, x, y, rng);
  }
};

struct AverageStage {
  Rgb* sum;
  float spp;
  RESTIR_HD void operator()(size_t i) const { sum[i] = sum[i] / spp; }  // a division, as every backend rounds it
};

struct TemporalStage {
  SsrPixelView v;
  PerspectiveCamera previous_camera;
  const GPacked* previous_g;
  const Rgb *history, *current;
  float alpha;
  Rgb* out;
  RESTIR_HD void operator()(int x, int y) const {
    out[size_t(y) * size_t(v.g.width) + size_t(x)] = temporal_pixel(v, previous_camera, previous_g, history, current, alpha, x, y);
  }
};

}  // namespace ssr_frame_detail

template <class B>
class SsrFrame final : public Integrator {
 public:
  using Exec = typename B::Exec;
  using Tracer = typename B::Tracer;
  explicit SsrFrame(const RenderContext& ctx) : ctx_(ctx) {
    const Bounds3 b = ctx.scene.bounds();
    extent_ = b.empty() ? 1.0f : std::max(1e-3f, length(b.diagonal()));
  }

  void render_frame(const FrameInfo& frame, Image& out) override {
    using namespace ssr_frame_detail;
    const RayCountScope counting(frame.stages, [this] { return world_.ray_totals(); });
    world_.update(ctx_, frame);
    width_ = frame.camera->width(), height_ = frame.camera->height();
    const size_t n = size_t(width_) * size_t(height_);
    reserve(n);
    Exec::zero(sum_, n);
    for (int s = 0; s < ctx_.options.render.spp; ++s) {
      primary(frame, s);
      direct(frame, s);
      reflections(frame, s);
      resolve(frame, s);
    }
    Exec::for_each(n, AverageStage{sum_.data, float(ctx_.options.render.spp)}, "averaging the samples");
    if (ctx_.options.ssr.temporal) temporal(frame);
    Exec::download(out.pixels.data(), sum_, n);
    sum_is_frame_ = true;
  }
  FrameBuffer frame_buffer() const override { return frame_buffer_of<Exec>(sum_, sum_is_frame_); }
  size_t buffer_bytes() const override {
    return array_bytes(rays_) + array_bytes(hits_) + array_bytes(g_) + array_bytes(previous_g_) + array_bytes(emitted_) + array_bytes(motion_) +
           array_bytes(hiz_) + array_bytes(lit_) + array_bytes(traced_) + array_bytes(sum_) + array_bytes(history_) +
           array_bytes(current_);
  }

 private:
  void reserve(size_t n) {
    rays_.reserve(n), hits_.reserve(n), g_.reserve(n), emitted_.reserve(n), lit_.reserve(n), sum_.reserve(n);
    traced_.reserve(n * size_t(ctx_.options.ssr.rays));
    animated_ = world_.view().animation_count > 0;  // motion vectors only where something can move
    if (animated_) motion_.reserve(n);
    layout_ = hiz_layout(width_, height_);
    hiz_.reserve(layout_.total);
  }
  GBufferView view(const FrameInfo& frame) const {
    return {g_.data,        width_, height_, animated_ ? motion_.data : nullptr, world_.view().world.scene.materials,
            emitted_.data, frame.camera->position()};
  }
  SsrPixelView pixel_view(const FrameInfo& frame) const {
    const PathWorld& w = world_.view().world;
    return {ctx_.options.ssr, *frame.camera, view(frame), HiZView{hiz_.data, layout_}, lit_.data, traced_.data, w.lights, extent_,
            w.ray_epsilon};
  }

  // Primary rays (one queue, traced coherently) and the G-buffer and Hi-Z pyramid built from them.
  void primary(const FrameInfo& frame, int s) {
    using namespace ssr_frame_detail;
    StageTimer timer(frame.stages, "primary");
    const FrameWorld<Tracer>& fw = world_.view();
    const size_t n = size_t(width_) * size_t(height_);
    Exec::for_pixels(width_, height_, CameraRayStage{camera_sampling(ctx_.options), *frame.camera, frame.index, s, rays_.data}, "ssr camera rays");
    B::trace_closest(world_, rays_.data, hits_.data, n, true);
    Exec::for_pixels(width_, height_,
                     GBufferStage{fw.world, rays_.data, hits_.data, g_.data, emitted_.data, animated_ ? motion_.data : nullptr, fw.back,
                                  fw.animation_count, width_},
                     "ssr G-buffer");
    const PerspectiveCamera& cam = *frame.camera;
    Exec::for_pixels(width_, height_, HiZBaseStage{g_.data, cam.position(), cam.forward(), hiz_.data, width_}, "ssr Hi-Z");
    const HiZView hiz{hiz_.data, layout_};
    for (int l = 1; l < layout_.levels; ++l)
      Exec::for_pixels(layout_.width[l], layout_.height[l], HiZReduceStage{hiz, l, hiz_.data + layout_.offset[l]}, "ssr Hi-Z");
  }

  // Lit colour: emission + direct light, the path tracer at depth 1 continuing the primary hits
  // (the same random numbers as path_radiance on the same camera ray: the same colour).
  void direct(const FrameInfo& frame, int s) {
    StageTimer timer(frame.stages, "direct");
    PathOptions depth1 = ctx_.options.path;
    depth1.max_depth = 1;
    const FrameWorld<Tracer>& fw = world_.view();
    const ssr_frame_detail::DirectStage<Tracer> stage{fw.world, fw.tracer, depth1, rays_.data, hits_.data, lit_.data,
                                                      width_,   uint32_t(frame.index), uint32_t(s), ctx_.options.render.seed};
    Exec::for_pixels(width_, height_, stage, "ssr direct light", frame.progress);
  }

  // ssr.rays BSDF-sampled rays per reflective pixel, marched through the screen.
  void reflections(const FrameInfo& frame, int s) {
    StageTimer timer(frame.stages, "reflections");
    const ssr_frame_detail::ReflectionStage stage{pixel_view(frame), traced_.data, uint32_t(frame.index), uint32_t(s),
                                                  ctx_.options.render.seed};
    Exec::for_pixels(width_, height_, stage, "ssr reflections");
  }

  // Each pixel's colour for this sample, added to sum_.
  void resolve(const FrameInfo& frame, int s) {
    StageTimer timer(frame.stages, "resolve");
    const ssr_frame_detail::ResolveStage stage{pixel_view(frame), sum_.data, uint32_t(frame.index), uint32_t(s), ctx_.options.render.seed};
    Exec::for_pixels(width_, height_, stage, "ssr resolve");
  }

  // ssr.temporal: blend the reflective pixels with the previous frame's (ssr_pixel.h), then keep
  // this frame and its (last sample's) G-buffer as the history.
  void temporal(const FrameInfo& frame) {
    StageTimer timer(frame.stages, "temporal");
    const size_t n = size_t(width_) * size_t(height_);
    if (frame.previous_camera && has_history_ && history_width_ == width_ && history_height_ == height_) {
      Exec::copy(current_, sum_, n);
      const ssr_frame_detail::TemporalStage stage{pixel_view(frame), *frame.previous_camera, previous_g_.data, history_.data,
                                                  current_.data,     ctx_.options.ssr.temporal_alpha, sum_.data};
      Exec::for_pixels(width_, height_, stage, "ssr temporal");
    }
    Exec::copy(history_, sum_, n);
    Exec::copy(previous_g_, g_, n);
    has_history_ = true, history_width_ = width_, history_height_ = height_;
  }

  RenderContext ctx_;
  typename B::World world_;
  float extent_ = 1;
  int width_ = 0, height_ = 0, history_width_ = 0, history_height_ = 0;
  bool animated_ = false, has_history_ = false, sum_is_frame_ = false;
  HiZLayout layout_;
  // Buffers in the backend's memory, allocated once per frame size and reused by every sample and frame.
  template <class T>
  using Array = typename Exec::template Array<T>;
  Array<Ray> rays_;
  Array<Hit> hits_;
  Array<GPacked> g_, previous_g_;
  Array<Rgb> emitted_;  // the emission toward the camera of this frame's primary hits
  Array<GMotion> motion_;
  Array<float> hiz_;
  Array<Rgb> lit_, sum_, history_, current_;
  Array<ReflectionRay> traced_;
};

}  // namespace rl
