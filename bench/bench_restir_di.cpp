// Equal-time comparison of ReSTIR DI against the path tracer's direct lighting (NEE + BSDF MIS) on
// the many-lights scene, measured in one run:
//   1. a converged reference (path tracer, path.max_depth = 1, many samples),
//   2. ReSTIR DI for a short sequence (static camera); its last frame is "one frame" in steady state,
//   3. the path tracer with as many samples per pixel as fit in the same wall time,
// and prints relMSE of both against the reference and their ratio (Bitterli et al. 2020 report
// 6-60x lower error at equal time; the aim is >= 20x).
// Then where a ReSTIR DI frame goes: the rays of one steady-state frame are logged and replayed
// through Embree alone (the same scalar queries, all cores), which gives the rays per pixel, the
// share of the frame they take, and the frame time that no work outside the rays can go below.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>

#include "bench_common.h"
#include "image/metrics.h"
#include "frame/render.h"
#include "scene/loader.h"

using namespace rl;

int main(int argc, char** argv) {
  CLI::App app{"ReSTIR DI vs path tracing at equal time"};
  std::string scene_path = std::string(RESTIR_SOURCE_DIR) + "/scenes/many-lights.pbrt";
  int width = 320, height = 180, frames = 8, reference_spp = 1024;
  app.add_option("--scene", scene_path);
  app.add_option("--width", width);
  app.add_option("--height", height);
  app.add_option("--frames", frames, "ReSTIR DI frames before the measured one (temporal history)");
  app.add_option("--reference-spp", reference_spp);
  std::vector<std::string> sets;
  app.add_option("--set", sets, "extra options for ReSTIR DI (key=value)");
  bool rays_only = false;
  app.add_flag("--rays-only", rays_only, "only where the frame goes (its rays replayed through Embree), no equal-time run");
  CLI11_PARSE(app, argc, argv);

  Scene scene = load_scene(scene_path);
  Options base;
  apply_scene_hints(base, scene.hints);
  base.film.width = width;
  base.film.height = height;
  base.path.max_depth = 1;
  // Centre-of-pixel primary rays for all three renders: the comparison is about the lighting
  // estimator, not about anti-aliasing the thousands of directly visible emitters.
  base.render.sample_pattern = SamplePattern::center;

  if (rays_only) {
    Options di = base;
    di.integrator = "restir-di";
    di.render.spp = 1;
    for (const auto& s : sets) set_option_assignment(di, s);
    bench::print_ray_share("ReSTIR DI", bench::ray_share(scene, di, std::min(frames, 3)));
    return 0;
  }
  Options ref = base;
  ref.render.spp = reference_spp;
  ref.render.seed = 12345;
  const Image reference = render(scene, ref).last;

  Options di = base;
  di.integrator = "restir-di";
  di.render.spp = 1;
  di.render.frames = frames;
  for (const auto& s : sets) set_option_assignment(di, s);
  RenderResult r_di = render(scene, di);
  // Frame 0 has no history: the median of the others (or frame 0 if it is the only one).
  const double di_ms = bench::median(r_di.frame_ms, r_di.frame_ms.size() > 1 ? 1 : 0);
  const double di_err = rel_mse(r_di.last, reference);

  Options pt1 = base;
  pt1.render.spp = 1;
  pt1.render.frames = 3;
  const double pt_ms_per_spp = bench::median(render(scene, pt1).frame_ms);
  const int spp = std::max(1, int(std::lround(di_ms / pt_ms_per_spp)));
  Options pt = base;
  pt.render.spp = spp;
  RenderResult r_pt = render(scene, pt);
  const double pt_err = rel_mse(r_pt.last, reference);

  fmt::print("scene {} at {}x{}, reference {} spp\n", scene_path, width, height, reference_spp);
  fmt::print("{:<28} {:>10} {:>12}\n", "", "ms/frame", "relMSE");
  fmt::print("{:<28} {:>10.1f} {:>12.5f}\n", fmt::format("ReSTIR DI (frame {})", frames), di_ms, di_err);
  fmt::print("{:<28} {:>10.1f} {:>12.5f}\n", fmt::format("path tracer NEE, {} spp", spp), r_pt.frame_ms[0], pt_err);
  fmt::print("equal-time relMSE ratio (PT / ReSTIR DI): {:.1f}x\n", pt_err / di_err * (r_pt.frame_ms[0] / di_ms));
  fmt::print("ReSTIR DI stages (median): {}\n", bench::stage_summary(r_di.frame_stages, r_di.frame_stages.size() > 1 ? 1 : 0));
  fmt::print("ReSTIR DI rays per pixel by stage (closest+any): {}\n",
             bench::ray_summary(r_di.frame_stages, double(width) * double(height), r_di.frame_stages.size() > 1 ? 1 : 0));
  fmt::print("ReSTIR DI buffers: {:.0f} bytes per pixel\n", double(r_di.buffer_bytes) / (double(width) * double(height)));
  bench::print_ray_share("ReSTIR DI", bench::ray_share(scene, di, std::min(frames, 3)));
  return 0;
}
