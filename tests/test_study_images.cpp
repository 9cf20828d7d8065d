// Study report pieces: the error maps' colour scale, the crop region, and the keys of per-frame
// references in animated scenes (suite "study"; the reports themselves: test_study.cpp).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

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
}
