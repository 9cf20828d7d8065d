// ReSTIR PT Enhanced's footprint reconnection criterion (pt.reconnection = footprint; Lin, Kettunen,
// Wyman 2026, sec. 4, eq. 5; walk.h) is unbiased: the hybrid shift re-tests it on the offset path
// with the offset path's own primary footprint, so ReSTIR PT stays equivalent to the reference path
// tracer (harness: tests/support/equivalence.h) on the shift-stressing stripes and mirror-glass
// scenes and on the Cornell box. And the harness sees the bias of a one-sided test (the base path's
// walk chooses x_k by the criterion, the offset path is never re-tested) in at least 9 of 10 repeats.
#include <doctest/doctest.h>

#include "equivalence.h"

using namespace rl;
using namespace rl::test;

namespace {

Options footprint_pt(const Scene& scene) {
  Options o = pt_certification_options(scene);
  set_option(o, "pt.shift", "hybrid");
  set_option(o, "pt.reconnection", "footprint");
  set_option(o, "path.russian_roulette", "false");
  return o;
}

}  // namespace

TEST_SUITE("slow_equivalence_footprint") {
  TEST_CASE("footprint reconnection: ReSTIR PT (stripes, mirror-glass, Cornell box) is equivalent to the path tracer") {
    for (const char* name : {"stripes.pbrt", "mirror-glass.pbrt"}) {
      const std::string path = own_scene(name);
      Scene scene = load_scene(path);
      certify_one(std::string("restir-pt hybrid footprint ") + name, path, scene, footprint_pt(scene),
                  certification(restir::ReuseMis::pairwise, 180, 180, 32768));
    }
    const std::string cornell = shared_scene("cornell-box/scene-v4.pbrt");
    Scene scene = load_scene(cornell);
    certify_one("restir-pt hybrid footprint cornell", cornell, scene, footprint_pt(scene),
                certification(restir::ReuseMis::pairwise, 100, 100, 16384));
  }
}

TEST_SUITE("slow_planted_footprint") {
  TEST_CASE("a one-sided footprint test (base path only) is detected in at least 9 of 10 repeats") {
    const std::string path = own_scene("stripes.pbrt");
    Scene scene = load_scene(path);
    const Options o = footprint_pt(scene);
    const Certification c = certification(restir::ReuseMis::pairwise, 300, 300, 65536);
    const auto& ref = reference_runs(path, scene, o, c.reference_spp, 8);
    PlantedBias one_sided;
    one_sided.footprint_one_sided = true;
    RenderHooks hooks;
    hooks.planted = &one_sided;
    int detected = 0;
    for (int r = 0; r < 10; ++r) {
      const EquivalenceReport rep = compare_runs(test_runs(scene, o, c.runs, 100000 + 10000 * uint64_t(r), 8, hooks), ref, c.spec);
      MESSAGE("repeat " << r << ": " << rep.describe());
      if (!rep.pass()) ++detected;
    }
    MESSAGE("one-sided footprint test: detected in " << detected << " of 10");
    CHECK(detected >= 9);
  }
}
