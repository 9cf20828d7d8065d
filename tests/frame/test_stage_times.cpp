// Per-stage frame timings (issue 9): every integrator reports where its frame time goes.
#include <doctest/doctest.h>

#include "frame/gbuffer.h"
#include "frame/integrator.h"
#include "frame/render.h"
#include "integrators/restir_di/restir_di_pixel.h"
#include "integrators/restir_pt/pt_path.h"
#include "scene/loader.h"
#include "test_helpers.h"

using namespace rl;
using namespace rl::test;

TEST_SUITE("stage_times") {
  TEST_CASE("stage names keep the frames' order; a stage first seen later goes after its predecessor") {
    StageTimes f0, f1;
    for (const char* s : {"primary", "candidates", "spatial", "shading"}) f0.add(s, 1);
    for (const char* s : {"primary", "candidates", "temporal", "spatial", "shading"}) f1.add(s, 1);
    f1.add("spatial", 2);  // a second chain adds to the same stage
    CHECK(f1.of("spatial") == 3);
    CHECK(f1.ms.size() == 5);
    CHECK(stage_names({f0, f1}) == std::vector<std::string>{"primary", "candidates", "temporal", "spatial", "shading"});
  }

  TEST_CASE("every integrator reports its stages, which add up to at most the frame time") {
    Scene scene = load_scene(shared_scene("cornell-box/scene-v4.pbrt"));
    for (const IntegratorInfo& info : integrator_registry()) {
      const std::string name = info.name;
      CAPTURE(name);
      Options o = options_for(scene, {"render.spp=1", "render.frames=2", "path.max_depth=3"});
      o.integrator = info.name;
      o = only_read_keys(o);  // path.max_depth: not restir-di's
      o.film.width = o.film.height = 8;
      RenderResult r = render(scene, o);
      REQUIRE(r.frame_stages.size() == 2);
      for (size_t f = 0; f < 2; ++f) {
        CHECK(!r.frame_stages[f].ms.empty());
        CHECK(r.frame_stages[f].total() <= r.frame_ms[f] * 1.001 + 0.01);
      }
      if (name.starts_with("restir-")) {
        CHECK(r.frame_stages[1].of("temporal") > 0);
        CHECK(r.frame_stages[0].of("temporal") == 0);
        CHECK(r.frame_stages[1].of("candidates") > 0);
      } else if (name == "pt") {
        CHECK(r.frame_stages[1].of("intersect") > 0);
        CHECK(r.frame_stages[1].of("shade") > 0);
      } else if (name == "ssr") {
        CHECK(r.frame_stages[1].of("reflections") > 0);
        CHECK(r.frame_stages[1].of("resolve") > 0);
      }
    }
  }

  // Issue 48's state per pixel: the benchmarks divide buffer_bytes by the pixels. A ReSTIR chain
  // holds at least this frame's and the previous frame's G-buffer (packed), this frame's emission
  // toward the camera, and three reservoir arrays (this frame's, the history and a pass's output)
  // per pixel and chain.
  TEST_CASE("every integrator on a backend frame reports its buffers, at least the arrays it must hold") {
    Scene scene = load_scene(shared_scene("cornell-box/scene-v4.pbrt"));
    struct Expect {
      const char* integrator;
      size_t at_least;  // bytes per pixel and chain
    } cases[] = {{"restir-di", 2 * sizeof(GPacked) + sizeof(Rgb) + 3 * sizeof(DiReservoir)},
                 {"restir-pt", 2 * sizeof(GPacked) + sizeof(Rgb) + 3 * sizeof(PathReservoir)},
                 {"pt", sizeof(Rgb)}};
    for (const Expect& e : cases)
      for (int spp : {1, 2}) {
        CAPTURE(e.integrator);
        CAPTURE(spp);
        Options o = options_for(scene, {"render.frames=2", "path.max_depth=3"});
        o.integrator = e.integrator;
        o = only_read_keys(o);
        o.render.spp = spp;
        o.film.width = 16, o.film.height = 12;
        const RenderResult r = render(scene, o);
        const double per_pixel = double(r.buffer_bytes) / (16.0 * 12.0);
        CHECK(per_pixel >= double(e.at_least) * (e.integrator[0] == 'r' ? spp : 1));
        CHECK(per_pixel < 64 * 1024);  // a sanity bound: no runaway allocation
      }
  }
}
