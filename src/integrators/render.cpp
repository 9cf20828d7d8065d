#include "integrators/render.h"

#include <fmt/format.h>

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <optional>

#include "core/parallel.h"
#include "integrators/integrator.h"
#include "scene/accel.h"
#include "scene/camera.h"
#include "scene/lights.h"

namespace rl {

void apply_scene_hints(Options& o, const SceneHints& h) {
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
void draw_progress(int frame, int frames, int done, int total, double elapsed_s) {
  const int width = 30;
  float f = (float(frame) + float(done) / float(total)) / float(frames);
  int filled = int(f * width);
  double eta = f > 0 ? elapsed_s * (1 - f) / f : 0;
  std::fprintf(stderr, "\r[%.*s%*s] %3d%%  frame %d/%d  ETA %.0fs ", filled, "##############################",
               width - filled, "", int(f * 100), frame + 1, frames, eta);
  std::fflush(stderr);
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

RenderResult render(const Scene& scene, const Options& o, const RenderHooks& hooks) {
  validate_options(o);
  ThreadLimit limit(o.render.threads);
  Camera camera = scene.camera;
  if (!o.render.camera_path.empty()) load_camera_path(o.render.camera_path, camera);
  if (camera.keys.empty()) camera.keys.push_back(CameraKey{});

  Accel accel(scene);
  Lights lights(scene, o.render.light_selection);
  RenderContext ctx{scene, accel, lights, o, hooks.planted};
  auto integrator = make_integrator(o.integrator, ctx);

  RenderResult result;
  result.average = Image(o.film.width, o.film.height);
  const bool bar = hooks.progress_bar && isatty(STDERR_FILENO);
  const auto start = std::chrono::steady_clock::now();
  std::optional<PerspectiveCamera> previous;
  for (int f = 0; f < o.render.frames; ++f) {
    PerspectiveCamera cam(camera.at_frame(f, o.render.frames), o.film.width, o.film.height);
    FrameInfo info;
    info.index = f;
    info.count = o.render.frames;
    info.camera = &cam;
    info.previous_camera = previous ? &*previous : nullptr;
    if (bar)
      info.progress = [&](int done, int total) {
        double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        draw_progress(f, o.render.frames, done, total, el);
      };
    Image img(o.film.width, o.film.height);
    StageTimes stages;
    info.stages = &stages;
    auto t0 = std::chrono::steady_clock::now();
    integrator->render_frame(info, img);
    double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    check_finite(o.integrator, f, img);
    result.frame_ms.push_back(ms);
    result.frame_stages.push_back(std::move(stages));
    // Running mean, numerically stable for long sequences.
    const float w = 1.0f / float(f + 1);
    for (size_t i = 0; i < img.size(); ++i) result.average.pixels[i] += (img.pixels[i] - result.average.pixels[i]) * w;
    if (hooks.on_frame) hooks.on_frame(f, img, ms);
    if (f + 1 == o.render.frames) result.last = std::move(img);
    previous = cam;
  }
  if (bar) std::fprintf(stderr, "\n");
  return result;
}

}  // namespace rl
