// Reports that conclude (issue 44): the paired comparison against the baseline and its 95%
// confidence intervals, bold only where a difference is resolved, one verdict line per plot,
// legends that name their key, tagged equal-time points, axes fitted to the data, and --quick
// refused for a study without a quick block.
#include <doctest/doctest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "study/paired.h"
#include "study/plots.h"
#include "study/report.h"
#include "study/results.h"
#include "study/study_file.h"
#include "test_helpers.h"

using namespace rl;
using namespace rl::study;
namespace fs = std::filesystem;

namespace {
fs::path temp_dir(const std::string& name) { return test::fresh_temp_dir("report-" + name); }

// Rows of one scene: configuration `value` of `key`, one row per seed 1, 2, ... with the given
// values of `metric`; render.seed varies with the seed, as in a study's rows.
void add(std::vector<Row>& rows, const std::string& key, const std::string& value, const std::vector<double>& v,
         const std::string& metric = "relmse", const std::string& scene = "scenes/a.pbrt") {
  for (size_t i = 0; i < v.size(); ++i) {
    Row r;
    r.scene = scene;
    r.config = "c" + value;
    r.seed = i + 1;
    r.options = {{key, value}, {"render.seed", std::to_string(i + 1)}, {"film.width", "32"}};
    r.metrics[metric] = v[i];
    rows.push_back(r);
  }
}

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}
}  // namespace

TEST_SUITE("study") {
  TEST_CASE("t quantiles and the paired 95% CI match a hand computation") {
    CHECK(t975(1) == doctest::Approx(12.7062).epsilon(1e-4));
    CHECK(t975(3) == doctest::Approx(3.1824).epsilon(1e-4));
    CHECK(t975(7) == doctest::Approx(2.3646).epsilon(1e-4));
    CHECK(t975(60) == doctest::Approx(2.0003).epsilon(1e-4));  // beyond the table: Cornish-Fisher
    CHECK(t975(1000) == doctest::Approx(1.9623).epsilon(1e-4));
    // Differences a − b per seed: 1, 2, 3, 6. Mean 3, sd sqrt(14/3), s.e. sd/2, half-width t(3) x s.e.
    SeedValues a = {{1, 11}, {2, 22}, {3, 33}, {4, 46}}, b = {{1, 10}, {2, 20}, {3, 30}, {4, 40}};
    Comparison c = compare(a, b);
    REQUIRE(c.paired);
    CHECK(c.diff.n == 4);
    CHECK(c.diff.mean == doctest::Approx(3.0));
    const double half = 3.1824 * std::sqrt(14.0 / 3.0) / 2.0;  // 3.437
    CHECK(c.diff.half == doctest::Approx(half).epsilon(1e-4));
    CHECK(c.diff.lo() < 0);  // [-0.44, 6.44]: includes 0
    CHECK_FALSE(c.resolved);
    // Ratios 1.1, 1.1, 1.1, 1.15: mean 1.1125.
    CHECK(c.ratio.mean == doctest::Approx(1.1125));
    // Seeds that share an offset: unpaired intervals overlap widely, the paired one excludes 0.
    a = {{1, 10.1}, {2, 20.2}, {3, 30.1}, {4, 40.2}};
    c = compare(a, b);
    CHECK(c.diff.mean == doctest::Approx(0.15));
    CHECK(c.diff.half == doctest::Approx(3.1824 * std::sqrt(0.01 / 3.0) / 2.0).epsilon(1e-4));
    CHECK(c.resolved);
    // Only one shared seed: unpaired, by non-overlapping intervals.
    c = compare({{1, 1.0}, {2, 1.1}, {3, 0.9}}, {{3, 5.0}, {4, 5.1}, {5, 4.9}});
    CHECK_FALSE(c.paired);
    CHECK(c.resolved);
    // No spread over seeds (noise: one value per configuration): no error estimate, never resolved.
    CHECK_FALSE(compare({{1, 1.0}, {2, 1.0}}, {{1, 2.0}, {2, 2.0}}).resolved);
  }

  TEST_CASE("bold only where the best is resolved against the runner-up; never in a constant column") {
    std::vector<Row> rows;
    add(rows, "k", "1", {1.0, 2.0, 1.5, 1.2});  // overlapping with "2"
    add(rows, "k", "2", {1.1, 1.9, 1.6, 1.0});
    CHECK(resolved_best(rows, "relmse", 0).empty());
    rows.clear();
    add(rows, "k", "1", {2.0, 2.1, 1.9, 2.05});
    add(rows, "k", "2", {1.0, 1.1, 0.9, 1.0});  // clearly lower
    add(rows, "k", "3", {3.0, 3.1, 2.9, 3.0});
    auto best = resolved_best(rows, "relmse", 0);
    REQUIRE(best.size() == 1);
    CHECK(best["scenes/a.pbrt"] == "c2");
    rows.clear();
    add(rows, "k", "1", {4, 4, 4}, "ms_median");  // a constant column
    add(rows, "k", "2", {4, 4, 4}, "ms_median");
    CHECK(resolved_best(rows, "ms_median", 0).empty());
    rows.clear();
    add(rows, "k", "1", {30, 31, 29}, "fps");  // fps: the highest is best
    add(rows, "k", "2", {60, 62, 61}, "fps");
    CHECK(resolved_best(rows, "fps", 0)["scenes/a.pbrt"] == "c2");
  }

  TEST_CASE("report.html: bold cells, the paired table against the baseline and a verdict per plot") {
    const fs::path d = temp_dir("html");
    Study s;
    s.name = "t";
    s.frames = 1;
    s.metrics = {"time", "relmse"};
    s.scenes = {"scenes/a.pbrt"};
    s.baseline = {{"k", "1"}};
    PlotSpec p;
    p.name = "relmse";
    p.x = "k";
    p.y = "relmse";
    s.plots = {p};
    std::vector<Row> rows;
    add(rows, "k", "1", {2.0, 2.1, 1.9, 2.05});
    add(rows, "k", "2", {1.0, 1.1, 0.9, 1.0});
    add(rows, "k", "3", {2.0, 2.3, 1.8, 2.1});
    add(rows, "k", "1", {1.0, 2.0, 1.5, 1.2}, "relmse", "scenes/b.pbrt");  // overlapping: no bold in scene b
    add(rows, "k", "2", {1.1, 1.9, 1.6, 1.0}, "relmse", "scenes/b.pbrt");
    for (auto& r : rows) r.metrics["ms_median"] = 5.0, r.metrics["fps"] = 200.0;  // constant columns: no bold
    std::vector<ReportConfig> configs;
    for (const char* v : {"1", "2", "3"}) configs.push_back({std::string("c") + v, "scenes/a.pbrt", {{"k", v}}, false});
    for (const char* v : {"1", "2"}) configs.push_back({std::string("c") + v, "scenes/b.pbrt", {{"k", v}}, false});
    PlotResult pr;
    pr.name = pr.title = "relmse";
    write_report(d.string(), s, rows, configs, {pr}, ReportInfo{});
    const std::string html = test::read_file(d / "report.html");
    CHECK(count(html, "<td class=\"best\">") == 1);  // relmse of k=2 in scene a, nothing else
    CHECK(html.find("Paired comparison against the baseline") != std::string::npos);
    CHECK(html.find("<td class=\"l better\">better</td>") != std::string::npos);             // k=2 vs k=1
    CHECK(html.find("<td class=\"l unresolved\">not resolved</td>") != std::string::npos);  // k=3 vs k=1
    CHECK(html.find("<p class=\"verdict\">relmse: a: k=2 lowest (1), resolved vs k=1") != std::string::npos);
    CHECK(html.find("; b: no resolved difference: k=2 lowest (1.4) vs k=1") != std::string::npos);
    fs::remove_all(d);
  }

  TEST_CASE("a plot's verdict line names the best configuration and whether it is resolved") {
    PlotSpec p;
    p.x = "pt.spatial_neighbors";
    p.y = "relmse";
    std::vector<Row> rows;
    add(rows, "pt.spatial_neighbors", "3", {2.0, 2.1, 1.9, 2.2});
    add(rows, "pt.spatial_neighbors", "5", {1.0, 1.1, 0.9, 1.0});
    add(rows, "pt.spatial_neighbors", "1", {4.0, 4.1, 3.9, 4.2});
    // 5 − 3 per seed: -1, -1, -1, -1.2: mean -1.05, sd 0.1, half-width 3.1824 x 0.05.
    CHECK(plot_verdict(p, rows, 0) ==
          "relmse: pt.spatial_neighbors=5 lowest (1), resolved vs pt.spatial_neighbors=3 (2.05; difference -1.05, "
          "95% CI [-1.209, -0.8909], 4 paired seeds)");
    rows.clear();
    add(rows, "pt.spatial_neighbors", "3", {1.1, 1.9, 1.6, 1.0});
    add(rows, "pt.spatial_neighbors", "5", {1.0, 2.0, 1.5, 1.2});
    add(rows, "pt.spatial_neighbors", "3", {1.0, 1.2}, "relmse", "scenes/b/scene-v4.pbrt");
    add(rows, "pt.spatial_neighbors", "5", {2.0, 2.2}, "relmse", "scenes/b/scene-v4.pbrt");
    const std::string two = plot_verdict(p, rows, 0);
    CHECK(two.rfind("relmse: a: no resolved difference: pt.spatial_neighbors=3 lowest (1.4) vs pt.spatial_neighbors=5", 0) == 0);
    CHECK(two.find("; b: pt.spatial_neighbors=3 lowest (1.1), resolved vs pt.spatial_neighbors=5") != std::string::npos);
    // Values computed across seeds (noise) have no interval: the line says so, no zero-width CI.
    rows.clear();
    add(rows, "k", "1", {2.0, 2.0}, "noise");
    add(rows, "k", "2", {1.0, 1.0}, "noise");
    p.y = "noise";
    CHECK(plot_verdict(p, rows, 0) == "noise: no resolved difference: k=2 lowest (1) vs k=1 (2; difference -1; one value "
                                      "per configuration (computed across seeds): no confidence interval)");
    rows.clear();
    add(rows, "pt.spatial_neighbors", "3", {1.1, 1.9, 1.6, 1.0});
    add(rows, "pt.spatial_neighbors", "5", {1.0, 2.0, 1.5, 1.2});
    p.y = "relmse";
    // Equal time: error x frame time decides.
    p.x = "ms_median";
    p.x_metric = true;
    for (auto& r : rows) r.metrics["ms_median"] = r.option("pt.spatial_neighbors") == "5" ? 0.1 : 1.0;
    CHECK(plot_verdict(p, rows, 0).rfind("relmse*ms_median (equal time: relmse x frame time): pt.spatial_neighbors=5 lowest", 0) == 0);
  }

  TEST_CASE("axes fitted to the data: log only over more than a decade, padded around min and max") {
    AxisFit f = fit_axis({1.0, 1.7, 2.5}, true);
    CHECK(f.valid);
    CHECK_FALSE(f.log);  // a log axis over 1..2.5 was 0.01..100
    CHECK(f.min > 0.9);
    CHECK(f.min < 1.0);
    CHECK(f.max > 2.5);
    CHECK(f.max < 2.6);
    f = fit_axis({0.01, 0.2, 1.0, -0.5 /* an error bar below 0: not on a log axis */}, true);
    CHECK(f.log);
    CHECK(f.min < 0.01);
    CHECK(f.min > 0.005);
    CHECK(f.max > 1.0);
    CHECK(f.max < 1.5);
    CHECK(fit_axis({0.05, 2.0}, false).min == 0.0);  // not below 0 for positive data
    CHECK(fit_axis({0.0, 2.0}, false).min < 0.0);    // a point at 0 is not drawn on the frame
    CHECK_FALSE(fit_axis({}, true).valid);
    CHECK(axis_commands("y", fit_axis({1.0, 2.5}, true)).find("logscale") == std::string::npos);
  }

  TEST_CASE("plots: the legend names the swept key; equal-time points carry their values; fitted ranges") {
    const fs::path d = temp_dir("plots");
    Study s;
    s.name = "t";
    PlotSpec et;
    et.name = "equal-time";
    et.x = "ms_median";
    et.x_metric = true;
    et.y = "relmse";
    et.series = "pt.spatial_neighbors";
    et.logx = et.logy = true;
    s.plots = {et};
    std::vector<Row> rows;
    for (const char* n : {"1", "3"})
      for (const char* spp : {"1", "2"})
        for (uint64_t seed : {1, 2}) {
          Row r;
          r.scene = "scenes/a.pbrt";
          r.config = std::string(n) + spp;
          r.seed = seed;
          r.options = {{"pt.spatial_neighbors", n}, {"render.spp", spp}, {"render.seed", std::to_string(seed)}};
          r.metrics["ms_median"] = 10.0 * std::atoi(spp) + double(seed);
          r.metrics["relmse"] = 1.0 + std::atoi(n) * 0.4 + 0.01 * double(seed);  // 1.4 .. 2.22: one linear axis
          rows.push_back(r);
        }
    const auto results = write_plots(s, rows, d.string());
    const std::string gp = test::read_file(d / "equal-time.gp"), dat = test::read_file(d / "equal-time.dat");
    CHECK(gp.find("set key title \"pt.spatial_neighbors\"") != std::string::npos);
    CHECK(gp.find("with labels") != std::string::npos);
    CHECK(count(dat, "\tspp=1\n") == 2);  // one point per (series, spp), tagged by its spp
    CHECK(count(dat, "\tspp=2\n") == 2);
    CHECK(gp.find("set logscale y") == std::string::npos);  // 1.4..2.2 is not a decade
    CHECK(gp.find("set yrange [") != std::string::npos);
    CHECK(gp.find("set xrange [") != std::string::npos);
    CHECK(legend_title("integrator+pt.shift") == "integrator + pt.shift");
    if (std::system("command -v gnuplot >/dev/null 2>&1") == 0) {
      REQUIRE(results.size() == 1);
      CHECK_MESSAGE(results[0].drawn, results[0].message);  // the script is valid gnuplot
    }
    fs::remove_all(d);
  }

  TEST_CASE("plots with more than 8 series: series 9 on has its own dash pattern and point shape") {
    const fs::path d = temp_dir("many-series");
    Study s;
    s.name = "t";
    PlotSpec ps;
    ps.name = "many";
    ps.x = "frame";
    ps.y = "relmse";
    ps.series = "di.max_history";
    s.plots = {ps};
    std::vector<Row> rows;
    for (int cap = 1; cap <= 10; ++cap)
      for (int frame = 0; frame < 2; ++frame) {
        Row r;
        r.scene = "scenes/a.pbrt";
        r.config = std::to_string(cap);
        r.seed = 1;
        r.frame = frame;
        r.options = {{"di.max_history", std::to_string(cap)}};
        r.metrics["relmse"] = 1.0 + 0.1 * cap + 0.01 * frame;
        rows.push_back(r);
      }
    const auto results = write_plots(s, rows, d.string());
    const std::string gp = test::read_file(d / "many.gp");
    // gnuplot repeats its 8 colours: line types 1 and 9 share one, the dash pattern and point tell them apart.
    CHECK(gp.find("lt 1 dt 1 lw 2 pt 7 ") != std::string::npos);
    CHECK(gp.find("lt 8 dt 1 lw 2 pt 7 ") != std::string::npos);
    CHECK(gp.find("lt 9 dt 2 lw 2 pt 5 ") != std::string::npos);
    CHECK(gp.find("lt 10 dt 2 lw 2 pt 5 ") != std::string::npos);
    if (std::system("command -v gnuplot >/dev/null 2>&1") == 0) {
      REQUIRE(results.size() == 1);
      CHECK_MESSAGE(results[0].drawn, results[0].message);  // the script is valid gnuplot
    }
    fs::remove_all(d);
  }

  TEST_CASE("--quick on a study without a quick block is an error; nothing is written") {
    const fs::path d = temp_dir("quick");
    const std::string json = "{\"name\": \"noquick\", \"scenes\": [\"" + test::own_scene("cornell-box.pbrt") +
                             "\"], \"base\": {\"integrator\": \"pt\", \"film.width\": 8, \"film.height\": 8}}";
    std::ofstream(d / "noquick.json") << json;
    CHECK_THROWS_WITH_AS(parse_study(json, (d / "noquick.json").string(), true),
                         doctest::Contains("study 'noquick' has no quick block (--quick needs one)"), StudyError);
    CHECK_NOTHROW(parse_study(json, (d / "noquick.json").string(), false));
    const auto r = test::run_restir("study " + (d / "noquick.json").string() + " --quick -q --out " + (d / "out").string());
    CHECK(r.status != 0);
    CHECK(r.output.rfind("error: ", 0) == 0);
    CHECK(r.output.find("has no quick block") != std::string::npos);
    CHECK_FALSE(fs::exists(d / "out"));
    fs::remove_all(d);
  }
}
