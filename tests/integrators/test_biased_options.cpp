// The named biased options are measured, not only labelled: the boiling filter (*.boiling_filter)
// and the duplication map (*.duplication_map, frame/reservoir_chain.h) against the path tracer with the equivalence harness
// (tests/support/equivalence.h) on the many-lights scene, where rare bright lights are what it
// drops. The image-mean bias and the worst 8x8 block are printed (README and docs/enhanced.md quote
// them); at full strength the harness must see the bias -- an option called biased that no
// measurement can tell from the unbiased estimator would be a mislabel, or a filter that does nothing.
#include <doctest/doctest.h>

#include "equivalence.h"

using namespace rl;
using namespace rl::test;

TEST_SUITE("slow_biased_options") {
  TEST_CASE("boiling filter: bias measured against the path tracer (many lights); at strength 1 the harness detects it") {
    const std::string path = own_scene("many-lights.pbrt");
    Scene scene = load_scene(path);
    const Certification c = certification(restir::ReuseMis::pairwise, 200, 200, 16384);
    for (const std::string strength : {"0", "0.2", "1"}) {
      Options o = options_for(scene, {"integrator=restir-di", "render.spp=1", "render.frames=8", "render.sample_pattern=center",
                                      "film.width=32", "film.height=16"});
      set_option(o, "di.boiling_filter", strength);
      const auto& ref = reference_runs(path, scene, o, c.reference_spp, 8);
      const EquivalenceReport rep = compare_runs(test_runs(scene, o, c.runs, 1000, 8), ref, c.spec);
      MESSAGE("di.boiling_filter=" << strength << ": " << rep.describe());
      if (strength == "0") CHECK(rep.pass());  // the unbiased control at the same budget
      if (strength == "1") CHECK(!rep.pass());
    }
  }

  TEST_CASE("duplication map: bias measured against the path tracer (many lights)") {
    const std::string path = own_scene("many-lights.pbrt");
    Scene scene = load_scene(path);
    const Certification c = certification(restir::ReuseMis::pairwise, 200, 200, 16384);
    Options o = options_for(scene, {"integrator=restir-di", "render.spp=1", "render.frames=8", "render.sample_pattern=center",
                                    "film.width=32", "film.height=16", "di.duplication_map=true"});
    const auto& ref = reference_runs(path, scene, o, c.reference_spp, 8);
    const EquivalenceReport rep = compare_runs(test_runs(scene, o, c.runs, 1000, 8), ref, c.spec);
    MESSAGE("di.duplication_map=true: " << rep.describe());
    CHECK(std::isfinite(rep.mean.rel));
  }
}
