// The project's own BVH on the CPU's cores (the traversal the CUDA backend runs, as the host twin
// render.backend = cpu-bvh runs it): the binary tree against the compressed 8-wide one
// (render.bvh = wide; Ylitie, Karras & Laine 2017) on the same rays, with Embree for scale.
//   - rays: those one path-traced frame traces (camera, bounce and shadow rays, recorded from the
//     reference path tracer) and as many random rays through the scene (incoherent);
//   - rounds interleave the layouts (binary, wide, binary, ...) so that a machine's drift hits both;
//     the median of each and the ratio wide / binary are reported, with the trees' sizes.
// The decision to make wide the default belongs to bench_gpu's CUDA kernels (issue 48); the CPU's
// scalar traversal is where the layouts' memory traffic and box tests can be compared without a GPU.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "backends/bvh_queries.h"
#include "bench_common.h"
#include "scene/loader.h"
#include "../tests/support/random_rays.h"

using namespace rl;
using Clock = std::chrono::steady_clock;

namespace {

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

// Closest hits of `rays` and any hits of `shadow` through q: milliseconds.
double trace_ms(const RayQueries& q, const std::vector<Ray>& rays, const std::vector<Ray>& shadow) {
  std::vector<Hit> hits(rays.size());
  std::vector<uint8_t> blocked(shadow.size());
  const auto t0 = Clock::now();
  q.intersect_batch(rays, hits);
  q.occluded_batch(shadow, blocked);
  return ms_since(t0);
}

void measure(const std::string& what, const Scene& scene, const std::vector<Ray>& rays, const std::vector<Ray>& shadow, int rounds) {
  const BvhQueries binary(scene, BvhLayout::binary), wide(scene, BvhLayout::wide);
  const Accel embree(scene);
  std::vector<double> tb, tw, te;
  for (int r = 0; r < rounds; ++r) {
    tb.push_back(trace_ms(binary, rays, shadow));
    tw.push_back(trace_ms(wide, rays, shadow));
    te.push_back(trace_ms(embree, rays, shadow));
  }
  const double b = bench::median(tb), w = bench::median(tw), e = bench::median(te);
  const double n = double(rays.size() + shadow.size());
  fmt::print("  {}: {} rays ({} shadow): binary {:.1f} ms = {:.1f} Mrays/s, wide {:.1f} ms = {:.1f} Mrays/s, wide/binary {:.3f} "
             "(min {:.3f}, max {:.3f}); Embree {:.1f} ms\n",
             what, rays.size() + shadow.size(), shadow.size(), b, n / b * 1e-3, w, n / w * 1e-3, w / b,
             *std::min_element(tw.begin(), tw.end()) / *std::max_element(tb.begin(), tb.end()),
             *std::max_element(tw.begin(), tw.end()) / *std::min_element(tb.begin(), tb.end()), e);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"the binary vs the compressed 8-wide BVH, traversed on the CPU: rays/s on the same rays"};
  int width = 640, height = 360, spp = 1, rounds = 5;
  std::vector<std::string> scenes = bench::scenes_by_size();
  app.add_option("--width", width);
  app.add_option("--height", height);
  app.add_option("--spp", spp);
  app.add_option("--rounds", rounds, "interleaved rounds per layout (the median is reported)");
  app.add_option("--scene", scenes, "scenes to measure");
  CLI11_PARSE(app, argc, argv);
  for (const std::string& path : scenes) {
    const Scene scene = load_scene(path);
    Options o;
    apply_scene_hints(o, scene.hints);
    o.integrator = "pt";
    o.film.width = width, o.film.height = height, o.render.spp = spp;
    const Accel accel(scene);
    const Lights lights(scene, o.render.light_selection);
    const RenderContext ctx{scene, accel, lights, o};
    const PerspectiveCamera cam(scene.camera.at_frame(0, 1), width, height);
    std::vector<Ray> rays, shadow;
    bench::record_rays(ctx, cam, rays, shadow);
    // Build times too: an animated scene's BVH is built again every frame.
    auto t0 = Clock::now();
    const Bvh b = build_bvh(scene, BvhLayout::binary);
    const double b_ms = ms_since(t0);
    t0 = Clock::now();
    const Bvh w = build_bvh(scene, BvhLayout::wide);
    const double w_ms = ms_since(t0);
    fmt::print("{} {}x{} {} spp: binary {} nodes ({:.2f} MB, depth {}, built in {:.0f} ms), wide {} nodes ({:.2f} MB, depth {}, {:.0f} ms)\n",
               path.substr(path.find_last_of('/') + 1), width, height, spp, b.nodes.size(), double(b.node_bytes()) * 1e-6, b.depth, b_ms,
               w.wide_nodes.size(), double(w.node_bytes()) * 1e-6, w.depth, w_ms);
    measure("path-traced frame", scene, rays, shadow, rounds);
    const std::vector<Ray> random = test::random_rays(scene, rays.size() + shadow.size(), 7);
    std::vector<Ray> closest(random.begin(), random.begin() + long(rays.size())), any(random.begin() + long(rays.size()), random.end());
    measure("random rays", scene, closest, any, rounds);
  }
  return 0;
}
