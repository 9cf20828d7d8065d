// Screen-space reflections (issue 12), measured in one run on the reflective scenes: frame time of
// ssr with the Hi-Z march and with the per-pixel march (the ratio of their "reflections" stages is
// the march's speed-up), each stage's share, and the path tracer's frame time at 1 spp for scale.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "bench_common.h"
#include "frame/render.h"
#include "scene/loader.h"

using namespace rl;

int main(int argc, char** argv) {
  CLI::App app{"screen-space reflections: Hi-Z vs per-pixel march, against the path tracer"};
  int width = 640, height = 360, frames = 4;
  app.add_option("--width", width);
  app.add_option("--height", height);
  app.add_option("--frames", frames, "frames per measurement (median; the first is skipped)");
  CLI11_PARSE(app, argc, argv);

  const std::string own = std::string(RESTIR_SOURCE_DIR) + "/scenes/";
  for (const char* name : {"mirror-floor.pbrt", "teapot-table.pbrt", "teapot.pbrt"}) {
    Scene scene = load_scene(own + name);
    Options base;
    apply_scene_hints(base, scene.hints);
    base.film.width = width;
    base.film.height = height;
    base.render.spp = 1;
    base.render.frames = frames;
    fmt::print("\n{} at {}x{}, 1 spp, median of frames 2-{}\n", name, width, height, frames);
    fmt::print("{:<22} {:>10}  {}\n", "integrator", "ms/frame", "stages");
    auto measure = [&](const char* label, Options o) {
      RenderResult r = render(scene, o);
      const double ms = bench::median(r.frame_ms, 1);
      fmt::print("{:<22} {:>10.1f}  {}\n", label, ms, bench::stage_summary(r.frame_stages, 1));
      std::vector<double> refl;
      for (const StageTimes& f : r.frame_stages) refl.push_back(f.of("reflections"));
      return std::pair(ms, bench::median(refl, 1));
    };
    Options pt = base;
    const double pt_ms = measure("pt", pt).first;
    Options ssr = base;
    ssr.integrator = "ssr";
    ssr.ssr.hi_z = false;
    const auto linear = measure("ssr (per-pixel march)", ssr);
    ssr.ssr.hi_z = true;
    const auto hiz = measure("ssr (Hi-Z)", ssr);
    ssr.ssr.resolve_neighbors = 0;
    measure("ssr (Hi-Z, no resolve)", ssr);
    fmt::print("march speed-up (reflections stage, per-pixel / Hi-Z): {:.2f}x; ssr (Hi-Z) frame / pt frame: {:.2f}\n",
               linear.second / std::max(hiz.second, 1e-9), hiz.first / std::max(pt_ms, 1e-9));
  }
}
