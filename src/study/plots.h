// Plots of a study, drawn by gnuplot (Debian package gnuplot-nox): for each plot spec, the data
// file NAME.dat (one block per series: x position, x label, mean, standard error, n over the
// pooled rows — seeds, and any axis that is neither x nor the series) and the script NAME.gp are
// written into plots/, then `gnuplot NAME.gp` draws NAME.png and NAME.svg. Edit the script and
// re-run it there to restyle a plot.
#pragma once
#include <string>
#include <vector>

#include "study/results.h"
#include "study/study_file.h"

namespace rl::study {

struct PlotResult {
  std::string name, title;
  bool drawn = false;   // PNG and SVG exist
  std::string message;  // why not
};

// Aggregated points of one plot: series label -> (x label, mean ± stderr).
struct PlotSeries {
  std::string label;
  struct Point {
    std::string x;
    double xpos = 0;
    Stat y;
    // Equal-time plots (x a metric): what tells this point's configuration from the others, e.g.
    // "spp=4" (the keys that differ, less the series keys; a key by its last component). The x
    // position is a measured time there, so without it a reader cannot tell which point is which.
    std::string tag;
  };
  std::vector<Point> points;
};
// Series are labelled by series_label (short, the baseline marked); on a categorical x each series
// sits at a small offset from the category (xpos = index + offset) so that none hides another.
std::vector<PlotSeries> aggregate(const PlotSpec& p, const std::vector<Row>& rows, bool* numeric_x = nullptr,
                                  const std::vector<std::pair<std::string, std::string>>& baseline = {});

// A series' legend text: the values of the series keys ("a+b") the row's integrator reads (pt.*
// only for restir-pt, di.* for restir-di and restir-pt with pt.direct=restir-di, gi.* for
// restir-gi, ssr.* for ssr, path.* for all but restir-di), joined by spaces, plus " (baseline)"
// when the row matches `baseline`. A scene is named by its file stem, an M-cap of 0 (*.max_history)
// "no cap".
std::string series_label(const std::string& series_key, const Row& r,
                         const std::vector<std::pair<std::string, std::string>>& baseline = {});
// Whether the row's integrator reads option `key` (the key's prefix names who reads it, as above).
bool reads_option(const std::string& key, const Row& r);
// A scene as legends and verdicts name it: its file stem, or the folder of a shared scene-v4.pbrt.
std::string scene_name(const std::string& scene);
// Drops the integrator's name from labels that say more than it, when the labels stay distinct
// ("restir-pt hybrid", "pt" -> "hybrid", "pt").
void shorten_labels(std::vector<PlotSeries>& series, const std::string& series_key);
// Axis text for a metric or key: what it is and its unit ("frame time (ms, median over frames)").
std::string axis_label(const std::string& name);

// An axis range fitted to the data (values: means and error-bar ends). Logarithmic only where
// want_log and the positive values span more than a decade (a log axis over 1..2.5 shows a decade
// of blank and squeezes the data); padded by `pad` of the span (of the decades on a log axis) on
// each side, and not below 0 for data above 0. valid: there were finite values.
struct AxisFit {
  bool valid = false, log = false;
  double min = 0, max = 1;
};
AxisFit fit_axis(const std::vector<double>& values, bool want_log, double pad = 0.05);
// The gnuplot lines for one axis ("x" or "y"): logscale where fitted so, and the range.
std::string axis_commands(const std::string& axis, const AxisFit& f);
// The legend's title: the series key(s) the legend's values are values of ("a+b" as "a + b").
std::string legend_title(const std::string& series_key);

// quick: the study ran with --quick; every plot's title says it is a smoke test.
std::vector<PlotResult> write_plots(const Study& s, const std::vector<Row>& rows, const std::string& plot_dir, bool quick = false);

}  // namespace rl::study
