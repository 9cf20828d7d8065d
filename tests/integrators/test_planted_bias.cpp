// Power of the convergence harness (tests/support/equivalence.h): biases planted through the resampling
// bridge (integrators/planted_bias.h) or the options must make the certification fail in at least
// 9 of 10 independent repeats (different seeds), at the CI tier's budget on the same
// configuration the certification uses. A harness that cannot detect a planted bias is no evidence
// of unbiasedness. The unbiased control passes in the certification matrix with the same budget.
#include <doctest/doctest.h>

#include "equivalence.h"

using namespace rl;
using namespace rl::test;

namespace {

struct Planted {
  const char* name;
  const char* scene;
  const char* mis;        // spatial and temporal MIS of the configuration
  const char* shift;
  PlantedBias bias;
  int runs;               // the CI tier's sequence count for this scene (test_restir_equivalence.cpp)
  int reference_spp;
};

// Detections among `repeats` independent certifications of the planted configuration.
int detections(const Planted& p, int repeats) {
  const std::string path = own_scene(p.scene);
  Scene scene = load_scene(path);
  Options o = pt_certification_options(scene);
  set_option(o, "pt.shift", p.shift);
  set_option(o, "pt.spatial_mis", p.mis);
  set_option(o, "pt.temporal_mis", p.mis);
  set_option(o, "path.russian_roulette", "false");
  // The margins of the unbiased MIS the planted configuration stands in for (constant MIS is judged
  // as the pairwise MIS it replaces).
  const Certification c = certification(restir::ReuseMis::pairwise, p.runs, p.runs, p.reference_spp);
  return planted_detections(p.name, path, scene, o, p.bias, c, repeats);
}

PlantedBias jacobian_off() {
  PlantedBias b;
  b.jacobian_scale = 1.1f;
  return b;
}
PlantedBias own_target_scaled() {
  PlantedBias b;
  b.own_target_scale = 1.02f;
  return b;
}
PlantedBias no_hybrid_check() {
  PlantedBias b;
  b.skip_hybrid_check = true;
  return b;
}

}  // namespace

TEST_SUITE("slow_planted") {
  TEST_CASE("planted biases: the harness detects each in at least 9 of 10 repeats") {
    const Planted planted[] = {
        {"jacobian x 1.1", "mirror-glass.pbrt", "pairwise", "hybrid", jacobian_off(), 180, 32768},
        {"neighbour's own target x 1.02", "mirror-glass.pbrt", "generalized-balance", "hybrid", own_target_scaled(), 180, 32768},
        {"hybrid invertibility check removed", "stripes.pbrt", "pairwise", "hybrid", no_hybrid_check(), 300, 65536},
        {"constant MIS in place of pairwise", "mirror-glass.pbrt", "constant", "hybrid", PlantedBias{}, 180, 32768},
    };
    for (const Planted& p : planted) {
      const int d = detections(p, 10);
      const std::string what = std::string(p.name) + ": detected in " + std::to_string(d) + " of 10 repeats";
      MESSAGE(what);
      INFO(what);
      CHECK(d >= 9);
    }
  }
}
