// Paired spatial reuse (frame/paired_reuse.h; Lin, Kettunen, Wyman 2026, sec. 3) is unbiased: with
// *.spatial_pairing = paired, ReSTIR PT (hybrid shift, on the shift-stressing stripes and
// mirror-glass scenes and the Cornell box), ReSTIR DI and ReSTIR GI (Cornell box) are equivalent
// to the reference path tracer (harness: tests/support/equivalence.h). And the harness sees the
// biases a wrong pairing would plant: a one-sided rejection in the shift pass and a broken
// involution, each detected in at least 9 of 10 repeats.
#include <doctest/doctest.h>

#include "equivalence.h"

using namespace rl;
using namespace rl::test;

namespace {

Options paired_pt(const Scene& scene, const char* shift) {
  Options o = pt_certification_options(scene);
  set_option(o, "pt.shift", shift);
  set_option(o, "pt.spatial_pairing", "paired");
  set_option(o, "path.russian_roulette", "false");
  return o;
}

Options paired_di(const Scene& scene) {
  return options_for(scene, {"integrator=restir-di", "render.spp=1", "render.frames=8", "render.sample_pattern=center",
                             "film.width=16", "film.height=16", "di.light_candidates=4", "di.spatial_neighbors=6",
                             "di.spatial_radius=4", "di.spatial_pairing=paired"});
}


}  // namespace

TEST_SUITE("slow_equivalence_paired") {
  TEST_CASE("paired spatial reuse: ReSTIR PT (stripes, mirror-glass, Cornell box), DI and GI are equivalent to the path tracer") {
    certify_shift_stressing("restir-pt hybrid paired", [](const Scene& scene) { return paired_pt(scene, "hybrid"); });
    const std::string cornell = shared_scene("cornell-box/scene-v4.pbrt");
    Scene scene = load_scene(cornell);
    certify_one("restir-pt reconnection paired cornell", cornell, scene, paired_pt(scene, "reconnection"),
                certification(restir::ReuseMis::pairwise, 100, 100, 16384));
    certify_one("restir-di paired cornell", cornell, scene, paired_di(scene), certification(restir::ReuseMis::pairwise, 100, 100, 16384));
    Options gi = options_for(scene, {"integrator=restir-gi", "render.spp=1", "render.frames=8", "render.sample_pattern=center",
                                     "film.width=16", "film.height=16", "path.max_depth=3", "gi.spatial_neighbors=6",
                                     "gi.spatial_radius=4", "gi.spatial_pairing=paired"});
    certify_one("restir-gi paired cornell", cornell, scene, gi, certification(restir::ReuseMis::pairwise, 100, 100, 16384));
  }

  TEST_CASE("planted pairing biases (one-sided rejection, broken involution) are detected in at least 9 of 10 repeats") {
    const std::string cornell = shared_scene("cornell-box/scene-v4.pbrt");
    Scene scene = load_scene(cornell);
    PlantedBias one_sided;
    one_sided.pairing_one_sided = true;
    PlantedBias broken;
    broken.pairing_broken = true;
    const Certification c = certification(restir::ReuseMis::pairwise, 100, 100, 16384);
    CHECK(planted_detections("one-sided rejection", cornell, scene, paired_di(scene), one_sided, c) >= 9);
    CHECK(planted_detections("broken involution", cornell, scene, paired_di(scene), broken, c) >= 9);
  }
}
