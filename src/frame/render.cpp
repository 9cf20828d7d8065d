#include "frame/render.h"

#include <fmt/format.h>

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <algorithm>
#include <optional>

#include "backends/cuda/cuda_queries.h"
#include "core/parallel.h"
#include "frame/denoiser.h"
#include "frame/integrator.h"
#include "backends/cpu/accel.h"
#include "scene/camera.h"
#include "scene/lights.h"

namespace rl {

void apply_scene_hints(Options& o, const SceneHints& h) {
  // What the scene asks for is not set explicitly: a scene written for pt (its max depth) may be
  // rendered by restir-di, which reads no path.* option. Restored on every way out.
  struct KeepExplicit {
    Options& o;
    std::vector<std::string> keys;
    ~KeepExplicit() { o.explicit_keys = std::move(keys); }
  } keep{o, o.explicit_keys};
  // A value the options refuse is reported where the scene file gave it (h.where: "file:line: ...").
  auto set = [&](const char* key, const std::string& value) {
    try {
      set_option(o, key, value);
    } catch (const OptionError& e) {
      auto w = h.where.find(key);
      if (w == h.where.end()) throw;
      throw OptionError(w->second + ": " + e.what());
    }
  };
  if (h.width) set("film.width", std::to_string(*h.width));
  if (h.height) set("film.height", std::to_string(*h.height));
  if (h.spp) set("render.spp", std::to_string(*h.spp));
  if (h.max_depth) set("path.max_depth", std::to_string(*h.max_depth));
  if (h.pixel_filter) set("film.filter", *h.pixel_filter);
  if (h.filter_radius) set("film.filter_radius", fmt::format("{}", *h.filter_radius));
}

namespace {

// A backend missing from the build or the machine (CUDA) is an option error here, before anything
// is built.
void check_backend(const RenderOptions& r) {
  if (r.backend == Backend::cuda)
    if (const std::string why = cuda_unavailable_reason(); !why.empty()) throw OptionError("render.backend = cuda: " + why);
  if (r.backend == Backend::cpu && r.bvh == BvhLayout::wide)
    throw OptionError("render.bvh = wide: the cpu backend traverses Embree's BVH; wide is the cuda and cpu-bvh backends' tree");
}
void draw_progress(int frame, int frames, int done, int total, double elapsed_s) {
  const int width = 30;
  float f = (float(frame) + float(done) / float(total)) / float(frames);
  int filled = int(f * width);
  double eta = f > 0 ? elapsed_s * (1 - f) / f : 0;
  std::fprintf(stderr, "\r[%.*s%*s] %3d%%  frame %d/%d  ETA %.0fs ", filled, "##############################",
               width - filled, "", int(f * 100), frame + 1, frames, eta);
  std::fflush(stderr);
}
// An animated scene at frame 0, still animated (animate_scene copies everything on first use).
Scene scene_at_frame_keeping_animation(const Scene& rest) {
  Scene s;
  animate_scene(rest, 0, s);
  return s;
}

// The one non-finite policy of every integrator: they never zero a NaN or infinity (the ReSTIR
// ones turn a non-finite target into a non-finite pixel, see mark_non_finite); the driver stops
// the render with the count and the first pixel.
void check_finite(const std::string& integrator, int frame, const Image& img) {
  size_t bad = 0, first = 0;
  for (size_t i = 0; i < img.size(); ++i)
    if (!is_finite(img.pixels[i]) && bad++ == 0) first = i;
  if (bad == 0) return;
  const size_t w = size_t(img.width);
  throw RenderError(integrator + ": " + std::to_string(bad) + " pixel(s) of frame " + std::to_string(frame) +
                    " had non-finite radiance (first at pixel " + std::to_string(first % w) + "," +
                    std::to_string(first / w) + "): a NaN or infinite value in the scene or a numerical failure");
}

}  // namespace

FrameRenderer::FrameRenderer(const Scene& scene, const Options& o, const PlantedBias* planted)
    : rest_(scene),
      animated_(scene_animated(scene) ? scene_at_frame_keeping_animation(scene) : Scene{}),
      scene_(scene_animated(scene) ? animated_ : scene),
      planted_(planted),
      o_(o) {
  validate_options(o_);
  limit_ = std::make_unique<ThreadLimit>(o_.render.threads);
  accel_ = std::make_unique<Accel>(scene_);
  check_backend(o_.render);
  lights_ = std::make_unique<Lights>(scene_, o_.render.light_selection);
  integrator_ = make_integrator(o_.integrator, context());
  denoiser_ = make_denoiser(o_);
  check_denoiser();
}

// A denoiser that needs re-shaded samples (A-SVGF) runs only after an integrator that gives them,
// which then keeps the history each frame starts from.
void FrameRenderer::check_denoiser() {
  if (!denoiser_ || !denoiser_->wants_reshade()) return;
  if (!integrator_->rerenders_previous())
    throw OptionError(fmt::format("denoise.method = {}: needs an integrator that can render the previous frame again "
                                  "(pt, restir-di, restir-gi, restir-pt); {} cannot (use denoise.method = svgf)",
                                  enum_name(o_.denoise.method), o_.integrator));
  integrator_->keep_history(true);
}

RenderContext FrameRenderer::context() const {
  return RenderContext{scene_, *accel_, *lights_, o_, planted_};
}

FrameRenderer::~FrameRenderer() = default;

void FrameRenderer::reset(const Options& o) {
  validate_options(o);
  find_integrator(o.integrator);  // an unknown name throws before anything is replaced
  // The new backend is checked first too: a missing CUDA device throws and leaves everything as it was.
  check_backend(o.render);
  integrator_.reset();            // it refers to o_ and the lights, replaced below
  const bool new_lights = o.render.light_selection != o_.render.light_selection;
  const bool new_limit = o.render.threads != o_.render.threads;
  o_ = o;
  if (new_limit) {
    limit_.reset();
    limit_ = std::make_unique<ThreadLimit>(o_.render.threads);
  }
  if (new_lights) lights_ = std::make_unique<Lights>(scene_, o_.render.light_selection);
  integrator_ = make_integrator(o_.integrator, context());
  denoiser_ = make_denoiser(o_);
  check_denoiser();
  denoised_ = Image();
  previous_.reset();
  before_previous_.reset();
  frame_ = 0;
}

void FrameRenderer::seek(int frame) {
  if (frame < 0 || frame >= o_.render.frames)
    throw OptionError(fmt::format("seek: frame {} is not in the sequence (render.frames = {}: 0 to {})", frame, o_.render.frames,
                                  o_.render.frames - 1));
  reset(Options(o_));  // no history: the integrator and the denoiser start over
  frame_ = frame;      // the scene moves to it (and its BVH and lights follow) in render_frame
}

void FrameRenderer::set_threads(int threads) {
  if (threads == o_.render.threads) return;
  Options o = o_;
  o.render.threads = threads;
  validate_options(o);
  o_.render.threads = threads;
  limit_.reset();
  limit_ = std::make_unique<ThreadLimit>(threads);
}

Options reference_options(const Options& defaults, const Options& o) {
  Options r = defaults;
  r.integrator = "pt";
  r.film = o.film;
  r.render.backend = o.render.backend;  // on the configuration's backend: a study on the GPU renders its references there
  r.path.max_depth = o.integrator == "restir-di" ? 1 : o.path.max_depth;
  r.render.camera_path.clear();
  r.output = OutputOptions{};
  r.denoise = DenoiseOptions{};  // a reference is the raw integral
  r.explicit_keys.clear();  // the reference is a configuration of its own: `o`'s keys were checked against o's integrator
  return r;
}

double FrameRenderer::render_frame(const CameraKey& key, int count, Image& out, StageTimes* stages,
                                   const std::function<void(int, int)>& progress) {
  const auto t0 = std::chrono::steady_clock::now();  // the frame's time includes moving the scene
  if (&scene_ == &animated_ && shown_frame_ != frame_) {  // move the scene to this frame; the BVH and lights follow
    StageTimer timer(stages, "animate");
    animate_scene(rest_, frame_, animated_);  // (the lights, when they move, are rebuilt below)
    shown_frame_ = frame_;
    accel_->update();
    if (lights_animated(rest_)) {  // static lights (only objects move) keep their tables
      Lights next(scene_, o_.render.light_selection);  // built first: a throw leaves the lights as they were
      previous_lights_ = std::make_unique<Lights>(std::move(*lights_));
      *lights_ = std::move(next);
    }
  }
  PerspectiveCamera cam(key, o_.film.width, o_.film.height);
  FrameInfo info;
  info.index = frame_;
  info.count = count;
  info.camera = &cam;
  info.previous_camera = previous_ ? &*previous_ : nullptr;
  info.previous_lights = previous_ && previous_lights_ ? previous_lights_.get() : nullptr;
  if (previous_ && &scene_ == &animated_ && integrator_->needs_previous_scene()) {
    StageTimer timer(stages, "animate");
    if (previous_shown_ != frame_ - 1) {  // the scene one frame earlier, and a BVH of it
      animate_scene(rest_, frame_ - 1, previous_scene_);
      if (previous_accel_) previous_accel_->update();
      else previous_accel_ = std::make_unique<Accel>(previous_scene_);
      previous_shown_ = frame_ - 1;
    }
    info.previous_scene = &previous_scene_;
    info.previous_accel = previous_accel_.get();
  }
  info.progress = progress;
  info.stages = stages;
  // A zeroed image of the film's size, as the integrators expect (some add their chains into it).
  if (out.width != o_.film.width || out.height != o_.film.height) out = Image(o_.film.width, o_.film.height);
  else std::fill(out.pixels.begin(), out.pixels.end(), Rgb(0));
  integrator_->render_frame(info, out);
  check_finite(o_.integrator, frame_, out);
  post_process(cam, out, stages);
  double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  before_previous_ = previous_;
  previous_ = cam;
  ++frame_;
  return ms;
}

// After the integrator, never inside it: the AOVs (the renderer's own primary rays) and the
// denoiser over the finished raw frame.
void FrameRenderer::post_process(const PerspectiveCamera& cam, const Image& raw, StageTimes* stages) {
  if (!aovs_requested_ && !denoiser_) return;
  {
    StageTimer timer(stages, "aovs");
    build_aovs(context(), cam, previous_ ? &*previous_ : nullptr, frame_, aovs_);
  }
  if (!denoiser_) return;
  if (denoiser_->wants_reshade() && previous_) {
    // A-SVGF: the previous frame's samples (its camera, its frame index: its random streams, and
    // for a ReSTIR integrator the history it started from) shaded in this frame's scene and
    // lights. Its own previous camera is frame f-2's; the history's lights are taken as they are
    // now (no previous_lights), so a sample of a light switched off has no target any more.
    StageTimer timer(stages, "reshade");
    FrameInfo info;
    info.index = frame_ - 1;
    info.count = frame_;
    info.camera = &*previous_;
    info.previous_camera = before_previous_ ? &*before_previous_ : nullptr;
    if (reshaded_.width != raw.width || reshaded_.height != raw.height) reshaded_ = Image(raw.width, raw.height);
    else std::fill(reshaded_.pixels.begin(), reshaded_.pixels.end(), Rgb(0));
    integrator_->rerender_previous(info, reshaded_);
    denoiser_->set_reshaded_previous(reshaded_);
  }
  StageTimer timer(stages, "denoise");
  denoiser_->denoise(raw, aovs_, denoised_);
}

void FrameRenderer::set_ray_log(RayLog* log) { accel_->set_ray_log(log); }

size_t FrameRenderer::buffer_bytes() const { return integrator_->buffer_bytes(); }

FrameBuffer FrameRenderer::frame_buffer(std::shared_ptr<const void>* owner) const {
  if (owner) *owner = integrator_;
  return integrator_->frame_buffer();
}

RenderResult render(const Scene& scene, const Options& o, const RenderHooks& hooks) {
  validate_options(o);
  Camera camera = scene.camera;
  if (!o.render.camera_path.empty()) load_camera_path(o.render.camera_path, camera);
  if (camera.keys.empty()) camera.keys.push_back(CameraKey{});
  FrameRenderer renderer(scene, o, hooks.planted);
  renderer.request_aovs(bool(hooks.on_aovs));

  RenderResult result;
  result.average = Image(o.film.width, o.film.height);
  const bool bar = hooks.progress_bar && isatty(STDERR_FILENO);
  const auto start = std::chrono::steady_clock::now();
  for (int f = 0; f < o.render.frames; ++f) {
    std::function<void(int, int)> progress;
    if (bar)
      progress = [&](int done, int total) {
        double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        draw_progress(f, o.render.frames, done, total, el);
      };
    Image img(o.film.width, o.film.height);
    StageTimes stages;
    double ms = renderer.render_frame(camera.at_frame(f, o.render.frames), o.render.frames, img, &stages, progress);
    result.frame_ms.push_back(ms);
    result.frame_stages.push_back(std::move(stages));
    accumulate_mean(result.average, img, f + 1);
    if (hooks.on_frame) hooks.on_frame(f, img, ms);
    if (hooks.on_aovs) hooks.on_aovs(f, renderer.aovs());
    if (hooks.on_denoised && !renderer.denoised().empty()) hooks.on_denoised(f, renderer.denoised());
    if (f + 1 == o.render.frames) {
      result.last = std::move(img);
      result.denoised = renderer.denoised();
    }
  }
  if (bar) std::fprintf(stderr, "\n");
  result.buffer_bytes = renderer.buffer_bytes();
  return result;
}

void accumulate_mean(Image& mean, const Image& img, int count) {
  // Running mean, numerically stable for long sequences.
  const float w = 1.0f / float(count);
  for (size_t i = 0; i < img.size(); ++i) mean.pixels[i] += (img.pixels[i] - mean.pixels[i]) * w;
}

}  // namespace rl
