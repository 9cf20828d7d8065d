// Path tracer throughput on the shared Cornell box and Veach MIS scenes, all measured in one run:
//   - path tracer rays/s and samples/s at 640x360,
//   - raw Embree throughput on exactly the rays the path tracer traced (recorded, then replayed
//     through Accel::intersect / occluded alone),
//   - the share of a frame spent inside Embree = replay time / frame time (goal: >= 60%),
//   - the wavefront path tracer (the integrator `pt`): ms/frame, rays/s (compare with Embree's
//     replay rate) and the share of its frame in the batched ray-query stages,
//   on the shared Cornell box and Veach MIS, and on the project teapot scene for contrast.
// Ratios, not absolute numbers, are what to compare across machines.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <chrono>
#include <mutex>

#include "bench_common.h"
#include "core/parallel.h"
#include "integrators/path/path_tracer.h"
#include "frame/render.h"
#include "scene/loader.h"

using namespace rl;
using Clock = std::chrono::steady_clock;

namespace {

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

struct FrameRun {
  double seconds = 0;
  PathStats stats;
  std::vector<Ray> rays, shadow_rays;
};

// One frame of the reference path tracer, row-parallel, optionally recording its rays.
FrameRun run_frame(const RenderContext& ctx, const PerspectiveCamera& cam, bool record) {
  const Options& o = ctx.options;
  FrameRun run;
  std::mutex m;
  auto t0 = Clock::now();
  parallel_for(o.film.height, [&](int y) {
    PathStats st;
    std::vector<Ray> rays, shadow;
    if (record) {
      st.record_rays = &rays;
      st.record_shadow_rays = &shadow;
    }
    for (int x = 0; x < o.film.width; ++x) {
      uint32_t pixel = uint32_t(y * o.film.width + x);
      for (int s = 0; s < o.render.spp; ++s) {
        Ray r = camera_ray(camera_sampling(ctx.options), cam, x, y, 0, s);
        Pcg32 rng = make_rng(pixel, 0, RngPass::path, o.render.seed, uint32_t(s));
        (void)path_radiance(ctx, o.path, r, rng, &st);
      }
    }
    std::lock_guard lock(m);
    run.stats.rays += st.rays;
    run.stats.shadow_rays += st.shadow_rays;
    if (record) {
      run.rays.insert(run.rays.end(), rays.begin(), rays.end());
      run.shadow_rays.insert(run.shadow_rays.end(), shadow.begin(), shadow.end());
    }
  });
  run.seconds = seconds_since(t0);
  return run;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"path tracer and Embree throughput benchmark"};
  int width = 640, height = 360, spp = 4, repeats = 3;
  app.add_option("--width", width);
  app.add_option("--height", height);
  app.add_option("--spp", spp);
  app.add_option("--repeats", repeats, "timed repetitions (the median is reported)");
  CLI11_PARSE(app, argc, argv);

  const std::string shared = std::string(RESTIR_SHARED_DIR) + "/scenes/", own = std::string(RESTIR_SOURCE_DIR) + "/scenes/";
  fmt::print("{:<12} {:>10} {:>12} {:>12} {:>14} {:>14} {:>10} {:>12} {:>12} {:>10}\n", "scene", "ms/frame", "Mrays/s(PT)",
             "Msamples/s", "Mrays/s(Embree)", "rays/sample", "in Embree", "wavefront ms", "Mrays/s(WF)", "in queries");
  // The two shared scenes the goal is stated for, and the project's teapots (9k triangles) for contrast.
  const std::pair<const char*, std::string> scenes[] = {{"cornell-box", shared + "cornell-box/scene-v4.pbrt"},
                                                        {"veach-mis", shared + "veach-mis/scene-v4.pbrt"},
                                                        {"teapot", own + "teapot.pbrt"}};
  for (const auto& [name, path] : scenes) {
    Scene scene = load_scene(path);
    Options o;
    apply_scene_hints(o, scene.hints);
    o.film.width = width;
    o.film.height = height;
    o.render.spp = spp;
    Accel accel(scene);
    Lights lights(scene, o.render.light_selection);
    RenderContext ctx{scene, accel, lights, o};
    PerspectiveCamera cam(scene.camera.at_frame(0, 1), width, height);

    run_frame(ctx, cam, false);  // warm-up
    std::vector<double> frame_s, embree_s;
    FrameRun rec = run_frame(ctx, cam, true);
    for (int i = 0; i < repeats; ++i) {
      frame_s.push_back(run_frame(ctx, cam, false).seconds);
      embree_s.push_back(bench::replay(accel, rec.rays, rec.shadow_rays));
    }
    // The integrator `pt` itself: the wavefront path tracer (same paths, same rays as run_frame's
    // path_radiance), with its stage times: "in queries" = the batched closest-hit and shadow stages.
    std::vector<double> wf_ms, query_share;
    for (int i = 0; i < repeats + 1; ++i) {
      RenderResult r = render(scene, o);
      if (i == 0) continue;  // warm-up (buffers allocated)
      wf_ms.push_back(r.frame_ms[0]);
      query_share.push_back((r.frame_stages[0].of("intersect") + r.frame_stages[0].of("shadow")) / r.frame_ms[0]);
    }
    const double tf = bench::median(frame_s), te = bench::median(embree_s), tw = bench::median(wf_ms) * 1e-3;
    double rays = double(rec.stats.rays + rec.stats.shadow_rays);
    double samples = double(width) * height * spp;
    fmt::print("{:<12} {:>10.1f} {:>12.2f} {:>12.3f} {:>14.2f} {:>14.2f} {:>9.0f}% {:>12.1f} {:>12.2f} {:>9.0f}%\n", name,
               tf * 1e3, rays / tf * 1e-6, samples / tf * 1e-6, rays / te * 1e-6, rays / samples, 100 * te / tf, tw * 1e3,
               rays / tw * 1e-6, 100 * bench::median(query_share));
  }
  return 0;
}
