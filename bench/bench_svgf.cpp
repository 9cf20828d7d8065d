// SVGF's cost against a ReSTIR DI frame (issue 46: SVGF at 640x360 on the CPU <= 10% of the frame),
// measured in the same frames of one run: restir-di with denoise.method=svgf, each frame's
// "denoise" stage (the filter) and "aovs" stage (the renderer's primary-ray pass that feeds it)
// against the rest of the frame (the integrator). Medians over frames 2..N.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "bench_common.h"
#include "frame/render.h"
#include "scene/loader.h"

using namespace rl;

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
  const RenderResult r = render(scene, o);
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
  return 0;
}
