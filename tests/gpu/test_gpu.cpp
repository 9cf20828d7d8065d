// restir_gpu_tests (issue 16): the CUDA backend against the CPU backend, on a machine with an
// NVIDIA GPU. Without a usable device it prints why and exits 77 (CTest: skipped). Run by
// scripts/gpu-check.sh.
#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include <cstdio>
#include <fstream>

#include "backends/bvh_queries.h"
#include "backends/cuda/cuda_queries.h"
#include "frame/render.h"
#include "scene/animation.h"
#include "query_agreement.h"
#include "random_rays.h"
#include "test_helpers.h"

using namespace rl;
using namespace rl::test;

namespace {

// RESTIR_GPU_DRY_RUN=1: the "GPU" side runs on the CPU (render.backend = cpu-bvh: the CUDA
// backend's code and BVH on the host), to check on a machine without a GPU that every scene loads
// and every case runs (GPU time is scarce).
bool g_dry_run = false;
// RESTIR_GPU_VERBOSE=1 prints each comparison's numbers, failing or not; RESTIR_GPU_SEEDS=K stacks K
// seeds (default 16) where the cases stack seeds: to see whether a difference shrinks with samples
// (the backends' rounding tipping a few paths) or stays (a bias).
//
// The two backends draw the same random numbers, so their images differ only where rounding tips
// a sampling or resampling choice (the device fuses multiply-adds). On the H200 (2026-12-04), 4
// seeds were too few for the glossy teapots: one 8x8 block off by 2.9% (pt) and 3.1% (restir-pt,
// random replay); with 16 seeds the worst blocks were 0.6% and 0.8%, and with 64 0.6%: noise
// that shrinks with samples, so the cases stack 16. The dry run stacks 4: there the "GPU" is the
// same CPU code (no fused multiply-adds, images nearly equal), and 16 would take 6 minutes of CI.
bool g_verbose = false;
int g_seeds = 16;
Backend gpu_backend() { return g_dry_run ? Backend::cpu_bvh : Backend::cuda; }
std::unique_ptr<RayQueries> gpu_queries(const Scene& scene, BvhLayout layout = BvhLayout::binary) {
  if (g_dry_run) return std::make_unique<BvhQueries>(scene, layout);
  return make_cuda_queries(scene, layout);
}

const std::vector<std::string>& test_scenes() {
  // The issue's three, plus spheres and 2400 emitters (many-lights) and an HDR environment map
  // (env-object): every kind of light the device copy of the lights must carry.
  static const std::vector<std::string> s = {shared_scene("cornell-box/scene-v4.pbrt"), shared_scene("veach-mis/scene-v4.pbrt"),
                                             own_scene("teapot.pbrt"), own_scene("many-lights.pbrt"), own_scene("env-object.pbrt")};
  return s;
}

// Whether the 8x8-block rule applies to a scene. Not in many-lights: its generator scatters 600
// emitter quads at the same height (y = 0.004), and where two of them overlap (differently bright),
// a camera ray meets both at the same distance, so which one it sees depends on the traversal
// order: Embree (the CPU backend) and the project's BVH (the CUDA backend and its host twin) choose
// differently. Measured (bench probe, 2026-12-04): in block (80, 72) at 128x96, 6 of 1024 camera
// rays hit another of two overlapping quads at the same t, and the block differs by 15.6% / 13.8% /
// 12.3% with 4 / 16 / 64 seeds (pt on the H200) and by the same 15.0% between the CPU and the host
// twin without a GPU (restir-di): a tie in the scene, not a sampling difference, so it does not
// shrink. test_bvh checks that the two traversals agree on hit and distance there.
bool blocks_comparable(const std::string& path) { return path.find("many-lights") == std::string::npos; }

// The path tracer's 8x8-block rule holds at 16 seeds (the GPU run: worst block 0.6% on the H200,
// 2026-12-04), not at the dry run's 4: Embree and the project's BVH round the teapot's glossy
// triangles' barycentrics differently, Russian roulette turns some of those into different
// survival decisions, and 4 seeds leave such a block up to 4.9% off (teapot) and 2.9% (features);
// without roulette the split paths reach fireflies instead (seed 1007: 29.8%). Measured on the
// host twin, 2026-12-05. So the dry run holds the path tracer to the image mean (and prints the
// blocks with RESTIR_GPU_VERBOSE=1); the ReSTIR cases keep their full rules.
bool pt_blocks(bool comparable) { return comparable && !g_dry_run; }

// The mean over the image of K seeds stacked (one image per seed, averaged).
Image stacked(const Scene& scene, Options o, int seeds) {
  Image sum(o.film.width, o.film.height);
  for (int k = 0; k < seeds; ++k) {
    o.render.seed = uint64_t(1000 + k);
    const Image img = render(scene, o).last;
    for (size_t i = 0; i < img.size(); ++i) sum.pixels[i] += img.pixels[i] / float(seeds);
  }
  return sum;
}

// The issue's agreement rule: image mean within 0.5%, every 8x8 block's mean within 2% (unless
// `blocks` is false: the mean alone).
void check_agree(const Image& cpu, const Image& gpu, bool blocks_too = true) {
  REQUIRE(cpu.size() == gpu.size());
  double a = 0, b = 0;
  for (size_t i = 0; i < cpu.size(); ++i) a += luminance(cpu.pixels[i]), b += luminance(gpu.pixels[i]);
  CHECK(a > 0);
  CHECK(std::fabs(b - a) <= 0.005 * a);
  if (g_verbose) MESSAGE("image mean: cuda / cpu - 1 = " << (b / a - 1));
  if (!blocks_too && !g_verbose) return;
  size_t bad = 0, blocks = 0;
  int worst_x = 0, worst_y = 0;
  double worst = 0;  // the largest relative block difference
  for (int by = 0; by + 8 <= cpu.height; by += 8)
    for (int bx = 0; bx + 8 <= cpu.width; bx += 8) {
      double ca = 0, cb = 0;
      for (int y = by; y < by + 8; ++y)
        for (int x = bx; x < bx + 8; ++x) ca += luminance(cpu.at(x, y)), cb += luminance(gpu.at(x, y));
      ++blocks;
      bad += std::fabs(cb - ca) > 0.02 * ca + 1e-6;
      if (std::fabs(cb - ca) / (ca + 1e-6) > worst) worst = std::fabs(cb - ca) / (ca + 1e-6), worst_x = bx, worst_y = by;
    }
  CAPTURE(blocks);
  CAPTURE(worst);
  if (g_verbose)
    MESSAGE("8x8 blocks: " << bad << " of " << blocks << " off by more than 2%; worst " << worst << " at (" << worst_x << ", " << worst_y
                           << ")" << std::string(blocks_too ? "" : " (not checked)"));
  if (blocks_too) CHECK(bad == 0);
}

}  // namespace

TEST_CASE("CUDA ray queries answer as the host traversal of the same BVH, binary and 8-wide") {
  for (const BvhLayout layout : {BvhLayout::binary, BvhLayout::wide})
  for (const std::string& path : {shared_scene("cornell-box/scene-v4.pbrt"), own_scene("teapot.pbrt"), own_scene("many-lights.pbrt")}) {
    CAPTURE(path);
    CAPTURE(int(layout));
    Scene scene = load_scene(path);
    const std::vector<Ray> rays = random_rays(scene, 200000, 3);
    BvhQueries host(scene, layout);
    const auto gpu = gpu_queries(scene, layout);
    // The device may fuse multiply-adds the host rounds twice: t to 1e-4, the same primitive
    // but at a shared edge.
    const QueryAgreement g = compare_queries(host, *gpu, rays, [](size_t, const Hit& h, const Hit& d, QueryAgreement& r) {
      r.t_mismatch += std::fabs(h.t - d.t) > 1e-4f * std::max(1.0f, h.t);
    });
    CHECK(g.hits > rays.size() / 10);
    CHECK(g.hit_mismatch + g.t_mismatch <= rays.size() / 10000);  // a hit missing or elsewhere
    CHECK(g.occluded_mismatch <= rays.size() / 10000);
  }
}

TEST_CASE("pt: CPU and CUDA renders agree (16 seeds stacked; mean 0.5%, 8x8 blocks 2%)") {
  for (const std::string& path : test_scenes()) {
    CAPTURE(path);
    Scene scene = load_scene(path);
    Options o = options_for(scene, {"film.width=128", "film.height=96", "render.spp=16"});
    const Image cpu = stacked(scene, o, g_seeds);
    o.render.backend = gpu_backend();
    check_agree(cpu, stacked(scene, o, g_seeds), pt_blocks(blocks_comparable(path)));
  }
}

// A scene with what the test scenes above lack: an image texture, a checkerboard (uv lookups on the
// device), a point light, a sphere light and an environment map together.
std::string feature_scene() {
  const std::string path = env_or("RESTIR_BINARY_DIR", RESTIR_BINARY_DIR) + "/gpu-features.pbrt";
  std::ofstream f(path);
  f << "LookAt 0 2.2 -4.5  0 0.4 0.5  0 1 0\nCamera \"perspective\" \"float fov\" 45\nWorldBegin\n"
       "LightSource \"infinite\" \"string filename\" \"" << shared_scene("envmaps/interior.exr") << "\" \"float scale\" 0.5\n"
       "Texture \"photo\" \"spectrum\" \"imagemap\" \"string filename\" \"" << shared_scene("envmaps/courtyard.exr") << "\" \"float uscale\" 2\n"
    << R"(Texture "checks" "spectrum" "checkerboard" "float uscale" 8 "float vscale" 8 "rgb tex1" [0.8 0.8 0.8] "rgb tex2" [0.1 0.1 0.1]
LightSource "point" "rgb I" [3 3 3] "point3 from" [1.5 2.5 -1]
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [8 6 4]
  Translate -1.2 1.4 0.3
  Shape "sphere" "float radius" 0.2
AttributeEnd
Material "diffuse" "texture reflectance" "checks"
Shape "trianglemesh" "point3 P" [ -3 0 -3 -3 0 3 3 0 3 3 0 -3 ] "point2 uv" [ 0 0 0 1 1 1 1 0 ] "integer indices" [ 0 1 2 0 2 3 ]
Material "diffuse" "texture reflectance" "photo"
Shape "trianglemesh" "point3 P" [ -0.8 0 0.8 0.8 0 0.8 0.8 1.4 0.8 -0.8 1.4 0.8 ] "point2 uv" [ 0 0 1 0 1 1 0 1 ] "integer indices" [ 0 1 2 0 2 3 ]
Material "conductor" "float roughness" 0.15
Shape "sphere" "float radius" 0.35
)";
  return path;
}

TEST_CASE("pt: textures, point, sphere and environment lights, and a pixel's samples across two waves") {
  {
    Scene scene = load_scene(feature_scene());
    Options o = options_for(scene, {"film.width=128", "film.height=96", "render.spp=16"});
    const Image cpu = stacked(scene, o, g_seeds);
    o.render.backend = gpu_backend();
    check_agree(cpu, stacked(scene, o, g_seeds), pt_blocks(true));
  }
  // 1024 x 1024 x 5 spp = 5.24 M paths: two waves of 2^22, and 5 does not divide 2^22, so pixel
  // 838860's samples are split between them (the per-pixel sums must add both parts, in order).
  Scene scene = load_scene(shared_scene("cornell-box/scene-v4.pbrt"));
  Options o = options_for(scene, {"film.width=1024", "film.height=1024", "render.spp=5"});
  const Image cpu = render(scene, o).last;
  o.render.backend = gpu_backend();
  check_agree(cpu, render(scene, o).last, pt_blocks(true));
}

TEST_CASE("an animated scene: the CUDA BVH follows the moving objects") {
  Scene scene = load_scene(own_scene("dynamic-room.pbrt"));
  Options o = options_for(scene, {"film.width=96", "film.height=64", "render.spp=16", "render.frames=4"});
  const Image cpu = render(scene, o).last;
  o.render.backend = gpu_backend();
  check_agree(cpu, render(scene, o).last);
}

TEST_CASE("an animated scene: after reset() at frame 3, frame 0 is drawn in frame 0's pose; CudaQueries::update") {
  Scene scene = load_scene(own_scene("dynamic-room.pbrt"));
  Options o = options_for(scene, {"film.width=96", "film.height=64", "render.spp=16"});
  const CameraKey key = scene.camera.at_frame(0, 1);
  Image cpu0, gpu0, scratch;
  FrameRenderer cpu(scene, o);
  cpu.render_frame(key, 4, cpu0, nullptr);
  FrameRenderer fr(scene, o);
  for (int i = 0; i < 4; ++i) fr.render_frame(key, 4, scratch, nullptr);  // the scene now shows frame 3
  o.render.backend = gpu_backend();
  fr.reset(o);
  fr.render_frame(key, 4, gpu0, nullptr);
  check_agree(cpu0, gpu0);
  // The ray queries of a scene that moves: update() follows it.
  Scene moving = scene;
  const auto queries = gpu_queries(moving);
  animate_scene(scene, 3, moving);
  queries->update();
  BvhQueries host(moving);
  const std::vector<Ray> rays = random_rays(moving, 100000, 9);
  std::vector<Hit> a(rays.size()), b(rays.size());
  host.intersect_batch(rays, a);
  queries->intersect_batch(rays, b);
  // As in the static scenes: the same hit or miss at the same distance. The primitive may differ
  // where two faces meet or overlap at that distance (the device fuses multiply-adds), so it is
  // counted, not checked; a BVH left in the old pose would move the distances of every ray that
  // meets a moved object.
  size_t mismatch = 0, other_prim = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    mismatch += a[i].valid() != b[i].valid() || (a[i].valid() && std::fabs(a[i].t - b[i].t) > 1e-4f * std::max(1.0f, a[i].t));
    other_prim += a[i].valid() && b[i].valid() && a[i].prim != b[i].prim;
  }
  CAPTURE(other_prim);
  if (g_verbose) MESSAGE("moved scene: " << mismatch << " hits differ, " << other_prim << " at another primitive");
  CHECK(mismatch <= rays.size() / 10000);
}

// A ReSTIR integrator's last frame (render.frames of history) on `backend`, K seeds stacked.
Image frames_stacked(const Scene& scene, Options o, int seeds, Backend backend) {
  o.render.backend = backend;
  return stacked(scene, o, seeds);
}

// Many-lights takes the image mean alone (blocks_comparable: overlapping emitter quads); the other
// scenes take the issue's full rule.
TEST_CASE("restir-di: CPU and CUDA renders agree (16 seeds stacked, 4 spp, 3 frames of reuse)") {
  for (const std::string& path : test_scenes()) {
    CAPTURE(path);
    Scene scene = load_scene(path);
    const Options o = options_for(scene, {"integrator=restir-di", "film.width=128", "film.height=96", "render.spp=4", "render.frames=3"});
    check_agree(frames_stacked(scene, o, g_seeds, Backend::cpu), frames_stacked(scene, o, g_seeds, gpu_backend()),
                blocks_comparable(path));
  }
}

// The ratio MIS weights of Pan et al. 2024 (restir/mis.h) in the device's combine() and paired
// resampling: asymmetric spatial (paired) and symmetric temporal, on the Cornell box's full rule.
TEST_CASE("restir-di and restir-pt: the ratio MIS weights on the CPU and CUDA agree (16 seeds stacked)") {
  const std::string path = shared_scene("cornell-box/scene-v4.pbrt");
  Scene scene = load_scene(path);
  for (const char* integrator : {"di", "pt"}) {
    const std::string p = integrator;
    CAPTURE(p);
    Options o = options_for(scene, {"film.width=128", "film.height=96", "render.spp=4", "render.frames=3", "path.max_depth=3",
                                    "path.russian_roulette=false"});
    set_option(o, "integrator", "restir-" + p);
    set_option(o, p + ".spatial_mis", "asymmetric-ratio");
    set_option(o, p + ".spatial_pairing", "paired");
    set_option(o, p + ".temporal_mis", "symmetric-ratio");
    o = only_read_keys(o);  // restir-di reads no path.* key
    check_agree(frames_stacked(scene, o, g_seeds, Backend::cpu), frames_stacked(scene, o, g_seeds, gpu_backend()),
                blocks_comparable(path));
  }
}

TEST_CASE("restir-di: render.backend = cuda through the renderer, textures and every kind of light, a debug view") {
  Scene scene = load_scene(feature_scene());
  Options o = options_for(scene, {"integrator=restir-di", "film.width=128", "film.height=96", "render.spp=4", "render.frames=3"});
  const Image cpu = render(scene, o).last;
  o.render.backend = gpu_backend();
  check_agree(cpu, render(scene, o).last);
  set_option_assignment(o, "render.debug_view=reuse-source");
  const Image gpu_view = render(scene, o).last;
  o.render.backend = Backend::cpu;
  check_agree(render(scene, o).last, gpu_view);
}

// The 8x8-block rule compares same-seed renders: it holds only as long as the two backends' paths
// stay together. Russian roulette in the sample point's path (path_bounce) splits them: the CPU's
// Embree and the project's BVH (the CUDA backend and its host twin) give the teapot's small glossy
// triangles slightly different barycentrics, so slightly different throughputs, and RR's threshold
// turns some of those into different survival decisions. Measured (dry run, seed 1000, teapot,
// frame 1, reuse off, 12288 pixels): RR on, 35 pixels differ by > 5%; RR off, none (largest
// difference 0.0016). Independent seeds differ by up to 66% a block, so each split path counts at
// full noise: with RR on, 4 seeds left one block at 2.2% and 16 seeds one at 2.1%. So the full
// rule runs without RR, and the renders with RR (the default) take the image-mean rule.
TEST_CASE("restir-gi: CPU and CUDA renders agree (16 seeds stacked, 4 spp, 3 frames of reuse)") {
  for (const std::string& path : {shared_scene("cornell-box/scene-v4.pbrt"), shared_scene("veach-mis/scene-v4.pbrt"), own_scene("teapot.pbrt")}) {
    CAPTURE(path);
    Scene scene = load_scene(path);
    for (bool roulette : {false, true}) {
      CAPTURE(roulette);
      Options o = options_for(scene, {"integrator=restir-gi", "film.width=128", "film.height=96", "render.spp=4", "render.frames=3",
                                      "path.max_depth=5"});
      o.path.russian_roulette = roulette;
      check_agree(frames_stacked(scene, o, g_seeds, Backend::cpu), frames_stacked(scene, o, g_seeds, gpu_backend()),
                  /*blocks_too=*/!roulette);
    }
  }
}

// The issue's scenes and rule, each shift; the teapot scene at depth 5 with ReSTIR DI for the direct
// light too (pt.direct = restir-di).
TEST_CASE("restir-pt: CPU and CUDA renders agree, each shift (16 seeds stacked, 4 spp, 3 frames of reuse)") {
  for (const std::string& path : {shared_scene("cornell-box/scene-v4.pbrt"), shared_scene("veach-mis/scene-v4.pbrt"), own_scene("teapot.pbrt")})
    for (const char* shift : {"pt.shift=hybrid", "pt.shift=reconnection", "pt.shift=random-replay"}) {
      const std::string shift_name = shift;
      CAPTURE(path);
      CAPTURE(shift_name);
      Scene scene = load_scene(path);
      // path.max_depth = 8: the Cornell box asks for 65 bounces, more than ReSTIR PT renders.
      const Options o = options_for(
          scene, {"integrator=restir-pt", "film.width=128", "film.height=96", "render.spp=4", "render.frames=3", "path.max_depth=8", shift});
      check_agree(frames_stacked(scene, o, g_seeds, Backend::cpu), frames_stacked(scene, o, g_seeds, gpu_backend()));
    }
  Scene scene = load_scene(own_scene("teapot.pbrt"));
  Options o = options_for(scene, {"integrator=restir-pt", "film.width=128", "film.height=96", "render.spp=4", "render.frames=3",
                                  "pt.direct=restir-di"});
  const Image cpu = render(scene, o).last;
  o.render.backend = gpu_backend();
  check_agree(cpu, render(scene, o).last);
}

// Resampled NEE (pt.nee_candidates): light tiles drawn on the device, environment candidates from
// the tiles' presampled directions (teapots), area lights of very different sizes (Veach MIS).
TEST_CASE("restir-pt: resampled NEE from light tiles on the CPU and CUDA agree (16 seeds stacked)") {
  for (const std::string& path : {own_scene("teapot.pbrt"), shared_scene("veach-mis/scene-v4.pbrt")}) {
    CAPTURE(path);
    Scene scene = load_scene(path);
    const Options o = options_for(scene, {"integrator=restir-pt", "film.width=128", "film.height=96", "render.spp=4", "render.frames=3",
                                          "path.max_depth=5", "pt.force_nee_reconnection=true", "pt.nee_candidates=4"});
    check_agree(frames_stacked(scene, o, g_seeds, Backend::cpu), frames_stacked(scene, o, g_seeds, gpu_backend()));
  }
}

// The pdf roughness proxy (pt.roughness_proxy = pdf, supplement §4): the walks' and the shifts'
// criteria read the sampling density on the device as on the CPU (glossy teapot-table, both
// criteria).
TEST_CASE("restir-pt: the pdf roughness proxy on the CPU and CUDA agree (16 seeds stacked)") {
  for (const char* criterion : {"pt.reconnection=roughness-distance", "pt.reconnection=footprint"}) {
    CAPTURE(criterion);
    Scene scene = load_scene(own_scene("teapot-table.pbrt"));
    const Options o = options_for(scene, {"integrator=restir-pt", "film.width=128", "film.height=96", "render.spp=4", "render.frames=3",
                                          "path.max_depth=5", "path.russian_roulette=false", "pt.roughness_proxy=pdf", criterion});
    check_agree(frames_stacked(scene, o, g_seeds, Backend::cpu), frames_stacked(scene, o, g_seeds, gpu_backend()));
  }
}

// Replay compaction (pt.replay_compaction): paired reuse's replaying shifts listed by the device's
// Exec::select (in the schedule's order) and made in a kernel of their own; each writes its own
// slot, so the frames agree with the CPU's as without compaction (hybrid on the teapots: prefixes
// and reconnections; random replay on env-object: every shift deferred).
TEST_CASE("restir-pt: replay compaction of paired reuse on the CPU and CUDA agree (16 seeds stacked)") {
  for (const char* shift : {"pt.shift=hybrid", "pt.shift=random-replay"}) {
    const std::string scene_name = std::string(shift) == "pt.shift=hybrid" ? "teapot.pbrt" : "env-object.pbrt";
    CAPTURE(scene_name);
    Scene scene = load_scene(own_scene(scene_name));
    const Options o = options_for(scene, {"integrator=restir-pt", "film.width=128", "film.height=96", "render.spp=4", "render.frames=3",
                                          "path.max_depth=5", "path.russian_roulette=false", "pt.spatial_pairing=paired",
                                          "pt.replay_compaction=true", shift});
    check_agree(frames_stacked(scene, o, g_seeds, Backend::cpu), frames_stacked(scene, o, g_seeds, gpu_backend()));
  }
}

// The reuse passes' shadow rays queued (render.reuse_rays = queued, frame/ray_slots.h): the
// producer, select, trace and consumer kernels on the device render what the CPU renders inline
// (on the host the two settings give the same image bit for bit: tests/frame/test_queued_rays.cpp).
TEST_CASE("render.reuse_rays = queued: restir-di, restir-gi and restir-pt on the CUDA backend agree with the CPU (16 seeds stacked)") {
  for (const auto& [scene_name, integrator] : {std::pair{"many-lights.pbrt", "integrator=restir-di"}, std::pair{"teapot.pbrt", "integrator=restir-gi"},
                                               std::pair{"teapot.pbrt", "integrator=restir-pt"}}) {
    const std::string name = scene_name, which = integrator;
    CAPTURE(name);
    CAPTURE(which);
    Scene scene = load_scene(own_scene(name));
    Options o = only_read_keys(options_for(scene, {integrator, "film.width=128", "film.height=96", "render.spp=4", "render.frames=3",
                                                   "path.max_depth=5", "path.russian_roulette=false"}));
    const Image cpu = frames_stacked(scene, o, g_seeds, Backend::cpu);
    o.render.reuse_rays = ReuseRays::queued;
    check_agree(cpu, frames_stacked(scene, o, g_seeds, gpu_backend()), blocks_comparable(name));
  }
}

// The compressed 8-wide BVH (render.bvh = wide) under whole frames: ReSTIR PT hybrid on the
// teapots and ReSTIR DI on many-lights (spheres, 2400 emitters) on the device as on the CPU.
TEST_CASE("render.bvh = wide: restir-pt and restir-di on the CPU and CUDA agree (16 seeds stacked)") {
  for (const auto& [scene_name, integrator] : {std::pair{"teapot.pbrt", "integrator=restir-pt"}, std::pair{"many-lights.pbrt", "integrator=restir-di"}}) {
    const std::string name = scene_name;
    CAPTURE(name);
    Scene scene = load_scene(own_scene(name));
    Options o = only_read_keys(options_for(scene, {integrator, "film.width=128", "film.height=96", "render.spp=4", "render.frames=3", "path.max_depth=5"}));
    const Image cpu = frames_stacked(scene, o, g_seeds, Backend::cpu);
    o.render.bvh = BvhLayout::wide;
    check_agree(cpu, frames_stacked(scene, o, g_seeds, gpu_backend()), blocks_comparable(name));
  }
}

// Animated scenes (one frame written once for every backend): each ReSTIR integrator's temporal
// reuse judges an animated history in the previous frame's scene, BVH and lights, on the device as
// on the CPU. 5 frames: the dynamic room's light switches and its occluder moves within them;
// moving-glossy's chrome teapot moves every frame. Without Russian roulette (its survival decisions
// split the backends' paths where their barycentrics round differently: see restir-gi above).
TEST_CASE("animated scenes: restir-di, restir-gi and restir-pt on the CPU and the CUDA backend agree") {
  for (const char* name : {"dynamic-room.pbrt", "moving-glossy.pbrt"}) {
    Scene scene = load_scene(own_scene(name));
    for (const char* integrator : {"integrator=restir-di", "integrator=restir-gi", "integrator=restir-pt"}) {
      const std::string scene_name = name, integrator_name = integrator;
      CAPTURE(scene_name);
      CAPTURE(integrator_name);
      const Options o = only_read_keys(options_for(scene, {integrator, "film.width=96", "film.height=64", "render.spp=4",
                                                           "render.frames=5", "path.max_depth=3", "path.russian_roulette=false",
                                                           "pt.shift=random-replay"}));
      check_agree(frames_stacked(scene, o, g_seeds, Backend::cpu), frames_stacked(scene, o, g_seeds, gpu_backend()));
    }
  }
}

// Issue 48: ssr on the GPU (ssr_frame.h). Its lit colour is the path tracer at depth 1, so the
// same 16 seeds stacked meet the path tracer's rule; the reflections march the G-buffer, which the
// two traversals fill with the same surfaces up to rounding. The temporal blend over 3 frames too.
TEST_CASE("ssr: CPU and CUDA renders agree (16 seeds stacked; mirror, glossy table, temporal, animated)") {
  struct Case {
    const char* scene;
    std::vector<const char*> sets;
  };
  for (const Case& c : {Case{"mirror-floor.pbrt", {}}, Case{"teapot-table.pbrt", {"ssr.rays=2"}},
                        Case{"mirror-floor.pbrt", {"ssr.temporal=true", "render.frames=3"}},
                        Case{"dynamic-room.pbrt", {"ssr.temporal=true", "ssr.roughness_cutoff=1", "render.frames=3"}}}) {
    CAPTURE(c.scene);
    Scene scene = load_scene(own_scene(c.scene));
    Options o = options_for(scene, {"integrator=ssr", "film.width=128", "film.height=96", "render.spp=2"});
    for (const char* kv : c.sets) set_option_assignment(o, kv);
    check_agree(frames_stacked(scene, o, g_seeds, Backend::cpu), frames_stacked(scene, o, g_seeds, gpu_backend()), pt_blocks(true));
  }
}

TEST_CASE("switching render.backend in a running FrameRenderer (the viewer's path)") {
  Scene scene = load_scene(shared_scene("cornell-box/scene-v4.pbrt"));
  Options o = options_for(scene, {"film.width=64", "film.height=64", "render.spp=64"});
  FrameRenderer fr(scene, o);
  Image cpu, gpu;
  fr.render_frame(scene.camera.at_frame(0, 1), 1, cpu, nullptr);
  o.render.backend = gpu_backend();
  fr.reset(o);
  fr.render_frame(scene.camera.at_frame(0, 1), 1, gpu, nullptr);
  check_agree(cpu, gpu);
}

int main(int argc, char** argv) {
  const char* dry = std::getenv("RESTIR_GPU_DRY_RUN");
  g_dry_run = dry && std::string(dry) == "1";
  const char* verbose = std::getenv("RESTIR_GPU_VERBOSE");
  g_verbose = verbose && std::string(verbose) == "1";
  if (g_dry_run) g_seeds = 4;
  if (const char* k = std::getenv("RESTIR_GPU_SEEDS")) g_seeds = std::max(1, std::atoi(k));
  if (g_dry_run) {
    std::printf("restir_gpu_tests: DRY RUN on the CPU (RESTIR_GPU_DRY_RUN=1): checks the cases, not the GPU\n");
  } else if (const std::string why = cuda_unavailable_reason(); !why.empty()) {
    std::printf("restir_gpu_tests: skipped: %s\n", why.c_str());
    return 77;
  } else {
    std::printf("restir_gpu_tests on %s\n", cuda_device_description().c_str());
  }
  doctest::Context ctx(argc, argv);
  return ctx.run();
}
