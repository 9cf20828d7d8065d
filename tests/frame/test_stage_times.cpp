// Per-stage frame timings (issue 9): every integrator reports where its frame time goes.
#include <doctest/doctest.h>

#include "frame/integrator.h"
#include "frame/render.h"
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
}
