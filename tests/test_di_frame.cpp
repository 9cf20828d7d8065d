// The CUDA backend's ReSTIR DI driver (di_frame.h) on the host (issue 16): run with the host
// execution policy over the BVH the GPU traverses, it must render what the CPU's restir-di renders
// on Embree -- the same stages, random streams, tiles, history and chains -- so that every part of
// the GPU's frame but the kernel launches is proven in CI.
#include <doctest/doctest.h>

#include <cmath>

#include "integrators/restir_di_cuda.h"
#include "frame_loop.h"
#include "test_helpers.h"

using namespace rl;
using namespace rl::test;

namespace {

// Share of pixels whose values agree to 1e-4 (relative, or absolute below 1e-3), and the ratio of
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

}  // namespace

TEST_SUITE("di_frame") {
  TEST_CASE("the CUDA backend's ReSTIR DI driver, run on the host, renders what the CPU's restir-di renders") {
    struct Case {
      const char* scene;
      std::vector<const char*> sets;
    };
    const std::vector<Case> cases = {
        {"many-lights.pbrt", {"render.spp=2"}},                                      // spheres, 2400 emitters, tiles, two chains
        {"env-object.pbrt", {"di.bsdf_candidates=2", "di.light_tiles=8"}},          // environment tiles, BSDF candidates
        {"env-object.pbrt", {"di.light_tiles=0", "di.visibility_reuse=false"}},      // no tiles; shadow rays in the weights
        {"mirror-glass.pbrt", {"di.temporal_mis=pairwise"}},                    // delta BSDFs (di_specular)
        {"many-lights.pbrt", {"di.spatial_rounds=2", "render.debug_view=reuse-source"}},  // two rounds, a debug view
    };
    for (const Case& c : cases) {
      CAPTURE(c.scene);
      const Scene scene = load_scene(own_scene(c.scene));
      Options o = options_for(scene, {"integrator=restir-di", "film.width=64", "film.height=48"});
      for (const char* s : c.sets) set_option_assignment(o, s);
      CAPTURE(o.di.light_tiles);
      const std::vector<Image> cpu = render_frames(scene, o, &make_cpu_restir_di, 3);
      const std::vector<Image> twin = render_frames(scene, o, &make_host_twin_restir_di, 3);
      for (int f = 0; f < 3; ++f) {
        CAPTURE(f);
        const Agreement a = agreement(cpu[size_t(f)], twin[size_t(f)]);
        MESSAGE(std::string(c.scene), " frame ", f, ": ", a.same * 100, "% of pixels agree, mean ratio ", a.mean_ratio);
        CHECK(a.same >= 0.99);
        CHECK(std::fabs(a.mean_ratio - 1) <= 0.005);
      }
    }
  }

  TEST_CASE("the driver refuses what it does not handle yet, naming it") {
    const Scene scene = load_scene(own_scene("dynamic-room.pbrt"));
    const Options o = options_for(scene, {"integrator=restir-di", "film.width=8", "film.height=8"});
    Accel accel(scene);
    Lights lights(scene, o.render.light_selection);
    const RenderContext ctx{scene, accel, lights, o, nullptr, nullptr};
    CHECK_THROWS_WITH(make_host_twin_restir_di(ctx), doctest::Contains("static scenes only"));
  }
}
