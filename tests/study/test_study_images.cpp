// Study report pieces: the error maps' colour scale, the crop region, the keys of per-frame
// references in animated scenes and a reference's own error (suite "study"; the reports
// themselves: test_study.cpp).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include <unistd.h>

#include "image/metrics.h"
#include "frame/render.h"
#include "scene/loader.h"
#include "study/images.h"
#include "study/references.h"
#include "study/runner.h"
#include "study/study_file.h"
#include "test_helpers.h"

using namespace rl;
using namespace rl::study;

TEST_SUITE("study") {
  TEST_CASE("error maps: the scale bar uses error_map()'s colours, labelled at 0, 0.25, 0.5, 0.75, 1") {
    const Image bar = error_scale_bar(240);
    REQUIRE(bar.width == 240);
    REQUIRE(bar.height > 20);
    // error_map() of an image against itself is 0 everywhere: the bar's left end.
    Image a(16, 16, Rgb(0.3f, 0.5f, 0.2f));
    a.at(3, 4) = Rgb(2.0f, 0.1f, 0.0f);
    const Image zero = error_map(a, a, OutputOptions{});
    CHECK(zero.at(5, 5) == bar.at(2, 5));
    CHECK(bar.at(2, 5) == Rgb(0));       // black = no error
    CHECK(bar.at(237, 5) == Rgb(1));     // white = error 1
    const Rgb mid = bar.at(120, 5);      // red-orange in between
    CHECK(mid.x == doctest::Approx(1.0));
    CHECK(mid.y > 0.3f);
    CHECK(mid.y < 0.7f);
    // A tick and a label (dark pixels) under each of the five values, and nothing dark elsewhere
    // between them in the tick row.
    auto dark = [&](int x0, int x1, int y0, int y1) {
      int n = 0;
      for (int y = y0; y < y1; ++y)
        for (int x = std::max(0, x0); x < std::min(bar.width, x1); ++x) n += bar.at(x, y).x < 0.5f;
      return n;
    };
    for (int i = 0; i <= 4; ++i) {
      const int x = 2 + int(std::lround(0.25 * i * 235));
      CAPTURE(i);
      CHECK(dark(x, x + 1, 14, 18) == 4);             // the tick
      CHECK(dark(x - 12, x + 12, 18, bar.height) > 4);  // its label
    }
    CHECK(dark(20, 40, 14, 18) == 0);
  }

  TEST_CASE("per-frame references are keyed by the animated state: a looping scene's alike frames share one") {
    const Study s = load_study(find_study("m-cap-long"), true);
    const Scene scene = load_scene(test::own_scene("blinking-room.pbrt"));  // on 0-49, off 50-99, every 100 frames
    const Options o = make_options(s, Options{}, expand(s)[0], 0);
    ReferenceCache cache("/nonexistent");
    auto key = [&](int f) { return cache.describe(s, scene, "blinking-room.pbrt", "text", Options{}, o, f).key; };
    CHECK(key(0) == key(49));
    CHECK(key(0) == key(100));
    CHECK(key(50) == key(99));
    CHECK(key(50) == key(1050));
    CHECK(key(0) != key(50));
    // In the dynamic room the sweeping light moves every frame: every frame has its own.
    const Scene room = load_scene(test::own_scene("dynamic-room.pbrt"));
    auto room_key = [&](int f) { return cache.describe(s, room, "dynamic-room.pbrt", "text", Options{}, o, f).key; };
    CHECK(room_key(3) != room_key(4));
    CHECK(room_key(40) == room_key(41));  // after the last key everything holds
  }

  TEST_CASE("crop_rect is the region zoom_crop shows") {
    for (auto [w, h] : {std::pair{320, 180}, std::pair{32, 18}, std::pair{7, 5}}) {
      CAPTURE(w);
      const CropRect r = crop_rect(w, h);
      Image im(w, h, Rgb(0));
      im.at(r.x0, r.y0) = Rgb(1, 0, 0);
      im.at(r.x0 + r.width - 1, r.y0 + r.height - 1) = Rgb(0, 1, 0);
      const Image c = zoom_crop(im, 4);
      CHECK(c.width == 4 * r.width);
      CHECK(c.height == 4 * r.height);
      CHECK(c.at(0, 0) == Rgb(1, 0, 0));
      CHECK(c.at(c.width - 1, c.height - 1) == Rgb(0, 1, 0));
    }
  }

  // references.h: a reference is rendered as two independent halves, and own_error() estimates
  // its relMSE from their difference. Checked against the truth: the reference's relMSE against a
  // render of the same options with 32x its samples (whose own error, 1/32 of the reference's, is
  // subtracted), restir-di's reference (direct light), 64x64. Over reference seeds 1-8 the ratio
  // estimate / truth was 0.84-1.39 (mean 1.07; 0.84 at the default seed used here). An estimate
  // from correlated halves (one seed) is 0 (planted: it fails), one without the n_A n_B / N²
  // factor 4x too large: both fall outside the [0.5, 2] band.
  TEST_CASE("a reference's own error, from its two halves, is its relMSE against a converged render") {
    namespace fs = std::filesystem;
    const std::string scene_path = test::own_scene("cornell-box.pbrt");
    const Scene scene = load_scene(scene_path);
    const Study s = parse_study("{\"scenes\": [\"" + scene_path + "\"], \"base\": {\"integrator\": \"restir-di\", "
                                "\"film.width\": 64, \"film.height\": 64}, \"metrics\": [\"relmse\"], \"reference\": {\"spp\": 32}}",
                                "/tmp/own-error.json", false);
    const Options defaults = test::options_for(scene, {});
    const Options o = make_options(s, defaults, expand(s)[0], 0);
    const fs::path dir = fs::temp_directory_path() / ("restir-own-error-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    ReferenceCache cache((dir / "references").string());
    const ReferenceJob job = cache.describe(s, scene, scene_path, "text", defaults, o, 0);
    REQUIRE(job.options.path.max_depth == 1);
    const Image ref = cache.get(job, scene);
    const double estimate = cache.own_error(job.key);
    Options converged = job.options;
    converged.render.spp = 1024;
    converged.render.seed = 4242;
    const double truth = rel_mse(ref, render(scene, converged, {}).last) - estimate / 32;
    INFO("estimate " << estimate << ", truth " << truth);
    CHECK(estimate > 0.5 * truth);
    CHECK(estimate < 2.0 * truth);
    // A reused reference reads its estimate back from its header, bit for bit.
    ReferenceCache again((dir / "references").string());
    again.get(job, scene);
    CHECK(again.reused() == 1);
    CHECK(again.own_error(job.key) == estimate);
    fs::remove_all(dir);
  }
}
