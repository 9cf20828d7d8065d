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
  };
  std::vector<Point> points;
};
std::vector<PlotSeries> aggregate(const PlotSpec& p, const std::vector<Row>& rows, bool* numeric_x = nullptr);

std::vector<PlotResult> write_plots(const Study& s, const std::vector<Row>& rows, const std::string& plot_dir);

}  // namespace rl::study
