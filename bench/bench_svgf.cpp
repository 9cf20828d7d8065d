// SVGF's cost against a ReSTIR DI frame (issue 46: SVGF at 640x360 on the CPU <= 10% of the frame),
// measured in the same frames of one run: restir-di with denoise.method=svgf, each frame's
// "denoise" stage (the filter) and "aovs" stage (the renderer's primary-ray pass that feeds it)
// against the rest of the frame (the integrator). Medians over frames 2..N.
// Then the same frames (their raw images and AOVs, kept from that run) through the CPU's
// vectorised Svgf and through SvgfStages<HostExec> (svgf_driver.h: the per-pixel stages the BVH
// backends share, render.backend = cpu-bvh), each frame timed with both, alternating which goes
// first: their time ratio, and the floats in which their outputs differ (0: the same filter).
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <chrono>
#include <cstring>

#include "backends/cpu/host_exec.h"
#include "bench_common.h"
#include "frame/render.h"
#include "post/svgf.h"
#include "post/svgf_driver.h"
#include "scene/loader.h"

using namespace rl;

namespace {

struct Input {
  Image raw;
  Aovs aovs;
};

double time_ms(const std::function<void()>& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// Svgf and SvgfStages<HostExec> over the same frames: their medians over frames 2..N (ms) and
// the floats in which their outputs differ over all frames.
void compare_stages(const std::vector<Input>& frames, const DenoiseOptions& o, int threads) {
  const ThreadLimit limit(threads);
  Svgf fast(o);
  SvgfStages<HostExec> stages(o);
  std::vector<double> fast_ms, stages_ms;
  size_t differing = 0, floats = 0;
  Image a, b;
  for (size_t f = 0; f < frames.size(); ++f) {
    const Input& in = frames[f];
    auto run_fast = [&] { fast_ms.push_back(time_ms([&] { fast.denoise(in.raw, in.aovs, a); })); };
    auto run_stages = [&] { stages_ms.push_back(time_ms([&] { stages.denoise(in.raw, in.aovs, b); })); };
    if (f % 2 == 0) run_fast(), run_stages();
    else run_stages(), run_fast();
    for (size_t i = 0; i < a.size(); ++i)
      for (int c = 0; c < 3; ++c) {
        const float x = a.pixels[i][c], y = b.pixels[i][c];
        differing += std::memcmp(&x, &y, sizeof(float)) != 0;
      }
    floats += 3 * a.size();
  }
  const double f_ms = bench::median(fast_ms, 2), s_ms = bench::median(stages_ms, 2);
  fmt::print("Svgf (vectorised rows) {:.1f} ms, SvgfStages<HostExec> (per-pixel stages, cpu-bvh) {:.1f} ms (medians of frames 2-{})\n",
             f_ms, s_ms, frames.size() - 1);
  fmt::print("SvgfStages<HostExec> / Svgf: {:.2f}   differing floats: {} of {}\n", s_ms / f_ms, differing, floats);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"SVGF cost per frame against ReSTIR DI's frame, in one run"};
  int width = 640, height = 360, frames = 6, threads = 0;
  std::string scene_path = std::string(RESTIR_SOURCE_DIR) + "/scenes/many-lights.pbrt";
  app.add_option("--scene", scene_path);
  app.add_option("--width", width);
  app.add_option("--height", height);
  app.add_option("--frames", frames, "frames (median of frames 2..N; the first has no history)");
  app.add_option("--threads", threads, "worker threads, 0 = all");
  CLI11_PARSE(app, argc, argv);

  const Scene scene = load_scene(scene_path);
  Options o;
  apply_scene_hints(o, scene.hints);
  set_option(o, "integrator", "restir-di");
  set_option(o, "film.width", std::to_string(width));
  set_option(o, "film.height", std::to_string(height));
  set_option(o, "render.spp", "1");
  set_option(o, "render.frames", std::to_string(frames));
  set_option(o, "render.threads", std::to_string(threads));
  set_option(o, "denoise.method", "svgf");
  std::vector<Input> inputs(static_cast<size_t>(frames));
  RenderHooks hooks;
  hooks.on_frame = [&](int f, const Image& img, double) { inputs[size_t(f)].raw = img; };
  hooks.on_aovs = [&](int f, const Aovs& a) { inputs[size_t(f)].aovs = a; };
  const RenderResult r = render(scene, o, hooks);
  std::vector<double> di, svgf, aovs;
  for (size_t f = 0; f < r.frame_ms.size(); ++f) {
    const double d = r.frame_stages[f].of("denoise"), a = r.frame_stages[f].of("aovs");
    svgf.push_back(d);
    aovs.push_back(a);
    di.push_back(r.frame_ms[f] - d - a);
  }
  const double di_ms = bench::median(di, 1), svgf_ms = bench::median(svgf, 1), aov_ms = bench::median(aovs, 1);
  fmt::print("{} at {}x{}, restir-di 1 spp, {} frames (median of frames 2-{})\n", scene_path, width, height, frames, frames);
  fmt::print("restir-di frame {:.1f} ms, svgf {:.1f} ms, aov pass {:.1f} ms\n", di_ms, svgf_ms, aov_ms);
  std::string each;
  for (double d : svgf) each += fmt::format(" {:.0f}", d);
  fmt::print("svgf ms by frame:{}   (frames 0-2 add the 7x7 variance estimate of pixels with < 4 frames of history)\n", each);
  fmt::print("svgf / restir-di frame: {:.3f}   (svgf + aov pass) / restir-di frame: {:.3f}\n", svgf_ms / di_ms,
             (svgf_ms + aov_ms) / di_ms);
  compare_stages(inputs, o.denoise, threads);
  return 0;
}
