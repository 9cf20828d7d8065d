// report.html: plots, each with its verdict line, configuration table (mean ± standard error over
// seeds, the best value bold only where resolved), the paired comparison of every configuration
// against the baseline (paired.h), image grids with zoomed crops (reference / each configuration /
// error map), machine and build info. Relative links only, no scripts or network: it opens from disk.
#pragma once
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "study/plots.h"
#include "study/results.h"
#include "study/study_file.h"

namespace rl::study {

struct ReportConfig {
  std::string config;  // configuration id (images/<config>*.png)
  std::string scene;
  std::vector<std::pair<std::string, std::string>> values;  // the axis values
  bool has_reference = false;
};

struct ReportInfo {
  int jobs = 1;
  bool quick = false;
  int references_rendered = 0, references_reused = 0;
  size_t jobs_run = 0, jobs_total = 0;
  size_t stale_rows = 0;  // stored rows recomputed because their inputs changed
  double seconds = 0;
};

// Per scene, the configuration whose `metric` the table bolds: the best mean (fps highest, else
// lowest) where it is resolved against the runner-up. Rule: the paired 95% CI of their per-seed
// difference excludes 0 (compare() in paired.h). Paired rather than "error bars do not overlap"
// because the configurations share seeds: the difference cancels what a seed's renders have in
// common, which unpaired bars count twice; it is the same test as the paired table and the plot
// verdicts, so the report never bolds what it calls unresolved elsewhere. No entry for a scene
// with one configuration, a tie at the top (a constant column), or values without spread over
// seeds (noise: computed across them).
std::map<std::string, std::string> resolved_best(const std::vector<Row>& rows, const std::string& metric, int last_frame);

std::string machine_description();  // CPU model and cores from /proc/cpuinfo
std::string build_description();     // version, compiler, build type

void write_report(const std::string& out_dir, const Study& s, const std::vector<Row>& rows,
                  const std::vector<ReportConfig>& configs, const std::vector<PlotResult>& plots, const ReportInfo& info);

}  // namespace rl::study
