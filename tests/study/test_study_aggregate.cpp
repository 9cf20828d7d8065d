// The study harness' aggregation of rows into plot series (mean and standard error over seeds)
// and its noise metric. Split from test_study.cpp (its parsing, runs and outputs) for length.
#include <doctest/doctest.h>

#include <cmath>

#include "image/image.h"
#include "study/images.h"
#include "study/plots.h"
#include "study/results.h"

using namespace rl;
using namespace rl::study;

TEST_SUITE("study") {
  TEST_CASE("aggregation: mean and standard error over seeds, one series per value") {
    std::vector<Row> rows;
    auto add = [&](const std::string& scene, const std::string& x, double y) {
      Row r;
      r.scene = scene;
      r.options = {{"di.spatial_neighbors", x}};
      r.metrics["relmse"] = y;
      rows.push_back(r);
    };
    add("a", "2", 1.0);
    add("a", "2", 3.0);
    add("a", "10", 5.0);
    add("b", "2", 7.0);
    PlotSpec p;
    p.x = "di.spatial_neighbors";
    p.y = "relmse";
    p.series = "scene";
    bool numeric = false;
    auto s = aggregate(p, rows, &numeric);
    CHECK(numeric);
    REQUIRE(s.size() == 2);
    REQUIRE(s[0].points.size() == 2);
    CHECK(s[0].points[0].x == "2");  // numeric order, not string order
    CHECK(s[0].points[0].y.mean == doctest::Approx(2.0));
    CHECK(s[0].points[0].y.stderr_ == doctest::Approx(1.0));  // sd sqrt(2) / sqrt(2)
    CHECK(s[0].points[1].y.n == 1);
    CHECK(s[1].points[0].y.mean == doctest::Approx(7.0));
  }

  TEST_CASE("noise: per-pixel standard deviation across seeds") {
    Image a(4, 2, Rgb(1.0f)), b(4, 2, Rgb(3.0f));
    CHECK(noise_across({a, b}) == doctest::Approx(std::sqrt(2.0)));
    CHECK(noise_across({a, a, a}) == doctest::Approx(0.0));
    CHECK(std::isnan(noise_across({a})));
  }
}
