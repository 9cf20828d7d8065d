// One frame per algorithm on every backend (issue 43): the CPU backend (Embree) and the CUDA
// backend's host twin (render.backend = cpu-bvh: the same frame over the project's BVH, the code
// the GPU runs but for the kernel launches) render the same image -- the same stages, random
// streams, tiles, history and chains -- up to the two traversals' rounding; and in animated
// scenes, whose history lives in the previous frame's scene, BVH and lights, the same
// distribution (slow_backends, with a planted bias it must see).
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "equivalence.h"
#include "frame_loop.h"
#include "test_helpers.h"

using namespace rl;
using namespace rl::test;

namespace {

// Share of pixels whose values agree to 1e-3 (relative, or absolute below 1e-3), and the ratio of
// the two images' means.
struct Agreement {
  double same = 0, mean_ratio = 0;
};
Agreement agreement(const Image& a, const Image& b) {
  size_t same = 0;
  double sa = 0, sb = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    bool ok = true;
    for (int c = 0; c < 3; ++c) {
      const float x = a.pixels[i][c], y = b.pixels[i][c];
      ok = ok && std::fabs(x - y) <= 1e-4f * std::max({std::fabs(x), std::fabs(y), 1e-3f}) * 10;
    }
    same += ok;
    sa += luminance(a.pixels[i]), sb += luminance(b.pixels[i]);
  }
  return {double(same) / double(a.size()), sb / sa};
}

// Renders each case with the CPU's integrator and with the twin, 3 frames, and compares frame by
// frame: at least min_same of the pixels equal (agreement()) and the means within 0.5%. Embree and
// the BVH traversal round hit distances differently, so a tipped resampling choice or a path that
// bounces differently makes a few pixels differ: measured 99.5-100% for ReSTIR DI, 99.3-100% for
// ReSTIR GI and 98.4-99.9% for ReSTIR PT. Long paths diverge further (no reuse at all, depth 5:
// mirror-glass's specular chains keep 80% for PT, env-object 96-98% for GI), hence the short depths
// below. A driver that breaks a stream, a buffer swap or a chain falls far below: planted, a
// missing swap after temporal reuse left 3-35% (DI), a path stream without its chain 0.3-0.7% (PT).
struct Case {
  const char* scene;
  std::vector<const char*> sets;
};
void check_twin(const char* integrator, double min_same, int width, int height, const std::vector<Case>& cases) {
  for (const Case& c : cases) {
    CAPTURE(c.scene);
    const Scene scene = load_scene(own_scene(c.scene));
    Options o = options_for(scene, {});
    o.integrator = integrator;
    o.film.width = width, o.film.height = height;
    for (const char* s : c.sets) set_option_assignment(o, s);
    const std::vector<Image> cpu = render_frames(scene, o, &make_registered, 3);
    Options bvh = o;
    bvh.render.backend = Backend::cpu_bvh;
    const std::vector<Image> twin = render_frames(scene, bvh, &make_registered, 3);
    for (int f = 0; f < 3; ++f) {
      CAPTURE(f);
      const Agreement a = agreement(cpu[size_t(f)], twin[size_t(f)]);
      MESSAGE(std::string(integrator), " ", std::string(c.scene), " frame ", f, ": ", a.same * 100,
              "% of pixels agree, mean ratio ", a.mean_ratio);
      CHECK(a.same >= min_same);
      CHECK(std::fabs(a.mean_ratio - 1) <= 0.005);
    }
  }
}

}  // namespace

TEST_SUITE("backends") {
  TEST_CASE("restir-di: the cpu-bvh backend renders what the cpu backend renders, frame by frame") {
    check_twin(
        "restir-di", 0.99, 64, 48,
        {
            {"many-lights.pbrt", {"render.spp=2"}},                                  // spheres, 2400 emitters, tiles, two chains
            {"env-object.pbrt", {"di.bsdf_candidates=2", "di.light_tiles=8"}},       // environment tiles, BSDF candidates
            {"env-object.pbrt", {"di.light_tiles=0", "di.visibility_reuse=false", "di.light_candidates=8"}},  // no tiles; shadow rays in the weights
            {"mirror-glass.pbrt", {"di.temporal_mis=pairwise"}},                     // delta BSDFs (di_specular)
            {"many-lights.pbrt", {"di.spatial_rounds=2", "render.debug_view=reuse-source"}},  // two rounds, a debug view
            {"many-lights.pbrt", {"render.spp=2", "di.spatial_mis=symmetric-ratio", "di.temporal_mis=asymmetric-ratio"}},  // Pan et al. 2024's weights
        });
  }

  TEST_CASE("restir-gi: the cpu-bvh backend renders what the cpu backend renders, frame by frame") {
    check_twin("restir-gi", 0.97, 48, 32,
               {
                   {"teapot.pbrt", {"render.spp=2", "path.max_depth=3"}},                  // two chains
                   {"env-object.pbrt", {"gi.target=radiance", "gi.spatial_mis=generalized-balance", "path.max_depth=3"}},  // the other target, MIS
                   {"mirror-glass.pbrt", {"path.max_depth=2"}},                             // delta BSDFs: plain path estimates
               });
  }

  TEST_CASE("restir-pt: the cpu-bvh backend renders what the cpu backend renders, frame by frame") {
    check_twin(
        "restir-pt", 0.97, 48, 32,
        {
            {"teapot.pbrt", {"render.spp=2"}},                                              // hybrid, two chains
            {"teapot.pbrt", {"pt.shift=reconnection", "pt.candidates=2"}},                  // reconnection, two walks
            {"env-object.pbrt", {"pt.shift=random-replay", "path.russian_roulette=true"}},  // replay, roulette
            {"mirror-glass.pbrt", {"pt.direct=restir-di", "path.max_depth=2"}},  // delta vertices; ReSTIR DI adds direct light
            {"teapot.pbrt", {"render.debug_view=reconnection-depth"}},           // a debug view (and its histogram)
            {"teapot.pbrt", {"pt.force_nee_reconnection=true", "pt.nee_candidates=4"}},  // resampled NEE from light tiles
            {"teapot.pbrt", {"pt.spatial_pairing=paired", "pt.replay_compaction=true", "pt.spatial_mis=asymmetric-ratio"}},  // compaction, ratio weights
        });
  }

  // Issue 48: ssr on every backend (its frame: ssr_frame.h).
  TEST_CASE("ssr: the cpu-bvh backend renders what the cpu backend renders, frame by frame") {
    check_twin("ssr", 0.97, 64, 48,
               {
                   {"mirror-floor.pbrt", {}},                                        // mirror reflections, the Hi-Z march
                   {"teapot-table.pbrt", {"ssr.hi_z=false", "ssr.rays=2"}},           // glossy: the resolve; the linear march
                   {"mirror-floor.pbrt", {"ssr.temporal=true", "render.spp=2"}},      // the temporal blend, two samples
                   {"dynamic-room.pbrt", {"ssr.temporal=true", "ssr.roughness_cutoff=1"}},  // animated: motion vectors
               });
  }
}

namespace {

// K independent sequences of `o` on one backend (seeds seed_base + i), each averaged over its
// frames, as 8x8-block means.
std::vector<BlockMeans> backend_runs(const Scene& scene, Options o, Backend backend, int runs, uint64_t seed_base,
                                     const PlantedBias* planted = nullptr) {
  o.render.backend = backend;
  RenderHooks hooks;
  hooks.planted = planted;
  return test_runs(scene, o, runs, seed_base, 8, hooks);
}

// Animated scenes on both backends, the same seeds stacked (1000, 1001, ...): the two draw the same
// random numbers, so they differ only where the traversals' rounding tips a choice, and a paired
// TOST on the image mean and every 8x8 block (compare_paired, equivalence.h) at the CI tier's
// margins (1% / 3%) has the power to see a bias far below the noise of either image.
EquivalenceReport animated_agreement(const char* scene_name, const char* integrator, const PlantedBias* planted_bvh = nullptr) {
  const Scene scene = load_scene(own_scene(scene_name));
  const Options o = only_read_keys(options_for(scene, {integrator, "film.width=32", "film.height=24", "render.spp=1",
                                                       "render.frames=6", "path.max_depth=3", "pt.shift=random-replay"}));
  constexpr int kRuns = 24;
  EquivalenceSpec spec;
  spec.mean_margin = 0.01, spec.block_margin = 0.03;
  return compare_paired(backend_runs(scene, o, Backend::cpu_bvh, kRuns, 1000, planted_bvh),
                        backend_runs(scene, o, Backend::cpu, kRuns, 1000), spec);
}

}  // namespace

TEST_SUITE("slow_backends") {
  TEST_CASE("animated scenes: every ReSTIR integrator on cpu-bvh is equivalent in distribution to the cpu backend") {
    for (const char* scene : {"dynamic-room.pbrt", "moving-glossy.pbrt"})
      for (const char* integrator : {"integrator=restir-di", "integrator=restir-gi", "integrator=restir-pt"}) {
        const std::string what = std::string(scene) + " " + integrator;
        CAPTURE(what);
        const EquivalenceReport r = animated_agreement(scene, integrator);
        MESSAGE(what, ": ", r.describe());
        CHECK(r.pass());
      }
  }

  TEST_CASE("the comparison sees a history judged in the wrong scene on one backend (planted on cpu-bvh)") {
    PlantedBias gi;
    gi.gi_history_cached = true;  // ReSTIR GI keeps an animated history's cached radiance
    const EquivalenceReport r = animated_agreement("dynamic-room.pbrt", "integrator=restir-gi", &gi);
    MESSAGE("planted, restir-gi: ", r.describe());
    CHECK_FALSE(r.pass());  // measured: mean -0.41% (se 0.07%), 2 of 12 blocks beyond 3%
  }
}
