// RGB resampling weights (pt.rgb_weights; ReSTIR PT Enhanced, Lin, Kettunen, Wyman 2026, sec. 6.3;
// mis.h's CombineInfo::color): the colour restir::combine sums over its inputs, Σ m_i F(Y_i) W_i
// |J_i|, is the expectation of F(Y) W_Y over its random selection of Y. Checked on real ReSTIR PT
// inputs: for a canonical pixel and three neighbours of the glossy teapots (hybrid shift) and the
// Cornell box, the mean of F(Y) W_Y over 4000 selections (each with its own random stream) must
// match the colour within 4 standard errors per channel, for pairwise and generalized-balance MIS.
// A colour that forgot the MIS weights, the Jacobians or 1/p̂ would miss it by far more.
#include <doctest/doctest.h>

#include <cmath>

#include "integrators/restir_pt/restir_pt_pixel.h"
#include "pt_fixture.h"
#include "restir/mis.h"

using namespace rl;
using namespace rl::test;

namespace {

struct ColorCheck {
  int checked = 0;    // input sets whose colour had a selectable path
  double worst = 0;   // largest |mean - colour| / se over channels and sets
  double worst_rel = 0;  // its relative difference
};

// planted: the colour weights divide by each input's own-domain target (PlantedBias::color_input_target).
ColorCheck check_color_expectation(PtFixture& fx, restir::ReuseMis mis, bool planted = false) {
  PathSettings ps;
  ps.pt.shift = ShiftMapping::hybrid;
  ps.path.max_depth = 4;
  const FrameWorld<EmbreeTracer> fw = fx.frame_world();
  const PtBridges<EmbreeTracer> bridges{fw, ps, true, PlantedBias{}, false};
  Pcg32 rng(99);
  ColorCheck out;
  for (int set = 0; set < 60 && out.checked < 12; ++set) {
    const GSurface* surfaces[4];
    const GPacked* packed[4];
    PathReservoir reservoirs[4];
    const PathReservoir* inputs[4];
    bool ok = true;
    for (int i = 0; i < 4 && ok; ++i) {
      surfaces[i] = &fx.random_surface(rng);
      packed[i] = fx.packed_of(*surfaces[i]);
      ok = surfaces[i]->valid;
      reservoirs[i] = initial_path_reservoir(fx.world(), fx.tracer(), ps, *surfaces[i], rng.next_u32(), 2);
      reservoirs[i].confidence = float(1 + i);  // unequal confidences: the MIS weights matter
      inputs[i] = &reservoirs[i];
    }
    if (!ok || !reservoirs[0].has_sample()) continue;
    const PtBridge<EmbreeTracer> bridge = bridges(fx.surface_list(*surfaces[0], packed), 4, false);
    const std::span<const PathReservoir* const> in(inputs, 4);
    restir::CombineInfo info;
    info.want_color = true;
    info.color_input_target = planted;
    Pcg32 first(1);
    (void)restir::combine(bridge, in, mis, first, &info);
    const Rgb color = info.color;
    constexpr int kDraws = 4000;
    double sum[3] = {0, 0, 0}, sq[3] = {0, 0, 0};
    for (int d = 0; d < kDraws; ++d) {
      Pcg32 r(uint64_t(d) + 7, 3);
      restir::CombineInfo again;
      again.want_color = true;
      again.color_input_target = planted;
      const PathReservoir res = restir::combine(bridge, in, mis, r, &again);
      REQUIRE(again.color == color);  // the colour does not depend on the selection
      const Rgb fw_y = res.has_sample() ? res.sample.contribution * res.ucw : Rgb(0);
      for (int c = 0; c < 3; ++c) sum[c] += fw_y[c], sq[c] += double(fw_y[c]) * fw_y[c];
    }
    for (int c = 0; c < 3; ++c) {
      const double mean = sum[c] / kDraws, var = sq[c] / kDraws - mean * mean;
      const double se = std::sqrt(std::max(var, 0.0) / kDraws);
      const double rel = std::fabs(mean - color[c]) / std::max(std::fabs(double(color[c])), 1e-12);
      // Float rounding (the colour sums w_i F / p̂ term by term, F(Y) W_Y divides the running Σw
      // once) is ~1e-6 relative, which matters where every input carries nearly the same F W.
      const double z = std::fabs(mean - color[c]) / (se + 2e-5 * std::fabs(mean) + 1e-12);
      if (z > out.worst) out.worst = z, out.worst_rel = rel;
    }
    ++out.checked;
  }
  return out;
}

}  // namespace

TEST_SUITE("restir_pt") {
  TEST_CASE("RGB resampling weights: the summed colour is E[F(Y) W_Y] over combine's selection (teapots, Cornell box)") {
    for (const std::string& path : {own_scene("teapot.pbrt"), shared_scene("cornell-box/scene-v4.pbrt")}) {
      PtFixture fx(path);
      for (restir::ReuseMis mis : {restir::ReuseMis::pairwise, restir::ReuseMis::generalized_balance}) {
        CAPTURE(path);
        CAPTURE(int(mis));
        const ColorCheck c = check_color_expectation(fx, mis);
        MESSAGE(path << " mis " << int(mis) << ": " << c.checked << " input sets, worst |mean - colour| = " << c.worst << " se (relative " << c.worst_rel << ")");
        CHECK(c.checked >= 8);
        CHECK(c.worst < 4.5);
      }
    }
    // The check's power: colours weighted by the inputs' own-domain targets miss by far.
    PtFixture fx(own_scene("teapot.pbrt"));
    const ColorCheck planted = check_color_expectation(fx, restir::ReuseMis::pairwise, true);
    MESSAGE("planted: worst |mean - colour| = " << planted.worst << " se (relative " << planted.worst_rel << ")");
    CHECK(planted.worst > 20);
  }

  TEST_CASE("*.rgb_weights: refused with one-over-z spatial MIS, for restir-gi, and for restir-di without visibility reuse") {
    Options o;
    o.integrator = "restir-pt";
    set_option(o, "pt.rgb_weights", "true");
    CHECK_NOTHROW(validate_options(o));
    set_option(o, "pt.spatial_mis", "one-over-z");
    CHECK_THROWS_WITH_AS(validate_options(o), doctest::Contains("pt.rgb_weights"), OptionError);
    Options gi;
    gi.integrator = "restir-gi";
    set_option(gi, "gi.rgb_weights", "true");
    CHECK_THROWS_WITH_AS(validate_options(gi), doctest::Contains("gi.rgb_weights"), OptionError);
    Options di;
    di.integrator = "restir-di";
    set_option(di, "di.rgb_weights", "true");
    CHECK_NOTHROW(validate_options(di));
    set_option(di, "di.visibility_reuse", "false");
    CHECK_THROWS_WITH_AS(validate_options(di), doctest::Contains("di.visibility_reuse"), OptionError);
  }
}
