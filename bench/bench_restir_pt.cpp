// ReSTIR PT's shift mappings against the path tracer, measured in one run, on a rough scene (the
// project Cornell box) and a glossy one (Veach MIS), at the same max depth:
//   - converged reference: the path tracer with many samples;
//   - each shift (reconnection, random replay, hybrid): ms per frame and relMSE of the last frame of
//     a short sequence (static camera, temporal + spatial reuse) — the thesis' figs. 4.3 / 5.4;
//   - the path tracer with as many samples as fit in each shift's frame time: equal-time relMSE ratio.
// --rays-only: instead, where a ReSTIR PT frame (hybrid, the glossy teapots) goes: its rays logged
// and replayed through Embree alone (bench_common.h, ray_share).
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>

#include "bench_common.h"
#include "image/metrics.h"
#include "frame/render.h"
#include "scene/loader.h"

using namespace rl;

int main(int argc, char** argv) {
  CLI::App app{"ReSTIR PT shift mappings vs path tracing"};
  int width = 160, height = 90, frames = 8, reference_spp = 2048, depth = 3;
  app.add_option("--width", width);
  app.add_option("--height", height);
  app.add_option("--frames", frames, "frames per sequence (the last one is measured)");
  app.add_option("--reference-spp", reference_spp);
  app.add_option("--depth", depth, "max depth of all renders");
  std::vector<std::string> sets;
  app.add_option("--set", sets, "extra options for ReSTIR PT (key=value), e.g. ReSTIR PT Enhanced's (docs/enhanced.md)");
  bool rays_only = false;
  app.add_flag("--rays-only", rays_only, "only where a hybrid frame on the teapots goes (its rays replayed through Embree)");
  CLI11_PARSE(app, argc, argv);

  const std::string shared = std::string(RESTIR_SHARED_DIR) + "/scenes/", own = std::string(RESTIR_SOURCE_DIR) + "/scenes/";
  const std::pair<const char*, std::string> scenes[] = {{"rough: cornell-box", own + "cornell-box.pbrt"},
                                                        {"glossy: veach-mis", shared + "veach-mis/scene-v4.pbrt"},
                                                        {"glossy: teapots", own + "teapot.pbrt"}};
  if (rays_only) {
    const Scene scene = load_scene(own + "teapot.pbrt");
    Options o;
    apply_scene_hints(o, scene.hints);
    o.film.width = width, o.film.height = height, o.path.max_depth = depth;
    o.integrator = "restir-pt";
    o.render.spp = 1;
    set_option(o, "pt.shift", "hybrid");
    bench::print_ray_share("ReSTIR PT (hybrid, teapots)", bench::ray_share(scene, o, std::min(frames, 3)));
    return 0;
  }
  for (const auto& [label, path] : scenes) {
    Scene scene = load_scene(path);
    Options base;
    apply_scene_hints(base, scene.hints);
    base.film.width = width;
    base.film.height = height;
    base.path.max_depth = depth;
    base.render.sample_pattern = SamplePattern::center;  // same primary hits everywhere: compare light transport
    Options ref = base;
    ref.render.spp = reference_spp;
    ref.render.seed = 777;
    const Image reference = render(scene, ref).last;
    Options pt1 = base;
    pt1.render.spp = 1;
    pt1.render.frames = 3;
    const double pt_ms_per_spp = bench::median(render(scene, pt1).frame_ms, 0);

    fmt::print("\n{} at {}x{}, depth {}, reference {} spp\n", label, width, height, depth, reference_spp);
    fmt::print("{:<14} {:>10} {:>12} {:>14} {:>12} {:>10}\n", "shift", "ms/frame", "relMSE", "PT equal-time", "PT relMSE",
               "ratio");
    for (const char* shift : {"reconnection", "random-replay", "hybrid"}) {
      Options o = base;
      o.integrator = "restir-pt";
      o.render.spp = 1;
      o.render.frames = frames;
      set_option(o, "pt.shift", shift);
      for (const auto& s : sets) set_option_assignment(o, s);
      RenderResult r = render(scene, o);
      const double ms = bench::median(r.frame_ms, 1);
      const double err = rel_mse(r.last, reference);
      Options pt = base;
      pt.render.spp = std::max(1, int(std::lround(ms / pt_ms_per_spp)));
      RenderResult rp = render(scene, pt);
      const double pt_err = rel_mse(rp.last, reference);
      // Residual time mismatch corrected to first order (error ∝ 1 / time).
      const double ratio = pt_err / err * (rp.frame_ms[0] / ms);
      fmt::print("{:<14} {:>10.1f} {:>12.5f} {:>10} spp {:>12.5f} {:>9.1f}x\n", shift, ms, err, pt.render.spp, pt_err, ratio);
      fmt::print("  stages: {}\n", bench::stage_summary(r.frame_stages, 1));
      fmt::print("  rays per pixel by stage (closest+any): {}\n",
                 bench::ray_summary(r.frame_stages, double(o.film.width) * double(o.film.height), 1));
      fmt::print("  buffers: {:.0f} bytes per pixel\n", double(r.buffer_bytes) / (double(o.film.width) * double(o.film.height)));
    }
  }
  return 0;
}
