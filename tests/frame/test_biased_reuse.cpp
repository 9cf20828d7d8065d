// The named biased reuse options of frame/reservoir_chain.h:
//  - RTXDI's boiling filter (*.boiling_filter): a reservoir whose W stands far above its 16x16
//    block's mean nonzero W is dropped, the others are kept; strength s sets the multiplier
//    10 / s - 9; in a render it removes energy, while 0 leaves the image bit for bit as it was;
//  - duplication maps (*.duplication_map; ReSTIR PT Enhanced sec. 5): the M-cap falls from
//    max_history toward 1 with the share D of the 17x17 window holding the same sample, as
//    lerp(max_history, 1, D^0.1); deterministic in a render.
#include <doctest/doctest.h>

#include "frame/render.h"
#include "frame/reservoir_chain.h"
#include "integrators/restir_di/restir_di_pixel.h"
#include "scene/loader.h"
#include "test_helpers.h"

using namespace rl;
using namespace rl::test;

namespace {

// The two stages over a w x h array of reservoirs with W = ucw[i], at `strength`; returns the W after.
std::vector<float> filtered(const std::vector<float>& ucw, int w, int h, float strength) {
  std::vector<DiReservoir> r(ucw.size());
  for (size_t i = 0; i < r.size(); ++i) r[i].ucw = ucw[i], r[i].target = 1, r[i].confidence = 1;
  const int bx = (w + 15) / 16, by = (h + 15) / 16;
  std::vector<float> means(size_t(bx) * size_t(by));
  const chain_detail::BoilingMeanStage<DiReservoir> mean{r.data(), means.data(), w, h, bx};
  for (size_t b = 0; b < means.size(); ++b) mean(b);
  const chain_detail::BoilingDropStage<DiReservoir> drop{r.data(), means.data(), w, bx, 10.0f / strength - 9.0f};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) drop(x, y);
  std::vector<float> out;
  for (const auto& x : r) out.push_back(x.ucw);
  return out;
}

double image_mean(const Image& img) {
  double s = 0;
  for (const Rgb& p : img.pixels) s += luminance(p);
  return s / double(img.pixels.size());
}

}  // namespace

TEST_SUITE("biased_reuse") {
  TEST_CASE("a reservoir far above its block's mean nonzero W is dropped; its neighbours and other blocks are kept") {
    const int w = 32, h = 20;  // 2 x 2 blocks, the lower ones partial
    std::vector<float> ucw(size_t(w) * h, 1.0f);
    ucw[5 * w + 5] = 200;   // block (0, 0): mean (255 + 200) / 256 = 1.78; 200 > 91 x 1.78
    ucw[5 * w + 6] = 0;     // zeros do not count in the mean
    ucw[3 * w + 20] = 100;  // block (1, 0): mean 1.39, 100 < 91 x 1.39 = 126: kept at strength 0.1
    const std::vector<float> out = filtered(ucw, w, h, 0.1f);  // multiplier 91
    CHECK(out[5 * w + 5] == 0);
    CHECK(out[3 * w + 20] == 100);
    CHECK(out[5 * w + 7] == 1);
    CHECK(out[18 * w + 30] == 1);
    // Strength 1: multiplier 1, anything above its block's mean goes.
    const std::vector<float> all = filtered(ucw, w, h, 1.0f);
    CHECK(all[3 * w + 20] == 0);
    CHECK(all[5 * w + 7] == 1);
  }

  TEST_CASE("in a ReSTIR DI render: 0 changes nothing, a strength removes energy (biased), the same on 1 and 2 threads") {
    Scene scene = load_scene(own_scene("many-lights.pbrt"));
    Options o = options_for(scene, {"integrator=restir-di", "render.spp=1", "render.frames=6", "film.width=64", "film.height=36"});
    const Image plain = render(scene, o).last;
    set_option(o, "di.boiling_filter", "0");
    CHECK(render(scene, o).last.pixels == plain.pixels);
    set_option(o, "di.boiling_filter", "1");
    const Image strong = render(scene, o).last;
    CHECK(image_mean(strong) < 0.98 * image_mean(plain));  // measured: -4%
    set_option(o, "render.threads", "1");
    CHECK(render(scene, o).last.pixels == strong.pixels);
  }

  TEST_CASE("duplication map: the M-cap is lerp(max_history, 1, D^0.1), D the window's share of the same sample") {
    const int w = 40, h = 30;
    std::vector<uint64_t> keys(size_t(w) * h);
    for (size_t i = 0; i < keys.size(); ++i) keys[i] = 1000 + i;  // all different
    for (int y = 0; y < 17; ++y)
      for (int x = 0; x < 17; ++x) keys[size_t(y) * w + size_t(x)] = 7;  // one sample copied over a 17x17 block
    keys[size_t(25) * w + 30] = keys[size_t(25) * w + 31] = 9;          // a pair
    keys[size_t(20) * w + 35] = 0;                                      // no sample
    std::vector<float> caps(keys.size());
    const chain_detail::DuplicationCapStage stage{keys.data(), caps.data(), w, h, 20.0f};
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) stage(x, y);
    CHECK(caps[size_t(8) * w + 8] == doctest::Approx(1.0f));  // the block's centre: D = 288 / 288
    const float pair = 20.0f - 19.0f * std::pow(1.0f / 288.0f, 0.1f);
    CHECK(caps[size_t(25) * w + 30] == doctest::Approx(pair));
    CHECK(caps[size_t(10) * w + 30] == 20.0f);  // unique
    CHECK(caps[size_t(20) * w + 35] == 20.0f);  // empty
    CHECK(caps[size_t(0) * w + 0] < caps[size_t(8) * w + 30]);  // the block's corner sees 80 copies
  }

  TEST_CASE("duplication map in ReSTIR DI and PT renders: it changes the image, the same on 1 and 2 threads") {
    Scene scene = load_scene(own_scene("many-lights.pbrt"));
    for (const char* integrator : {"restir-di", "restir-pt"}) {
      Options o = options_for(scene, {"render.spp=1", "render.frames=6", "film.width=48", "film.height=27"});
      set_option(o, "integrator", integrator);
      if (std::string(integrator) == "restir-pt") set_option(o, "path.max_depth", "2");
      const std::string group = std::string(integrator) == "restir-di" ? "di" : "pt";
      const Image plain = render(scene, o).last;
      set_option(o, group + ".duplication_map", "true");
      const Image capped = render(scene, o).last;
      CHECK(capped.pixels != plain.pixels);
      set_option(o, "render.threads", "1");
      CHECK(render(scene, o).last.pixels == capped.pixels);
    }
  }
}
