// report.html: plots, configuration table (mean ± standard error over seeds), image grids with
// zoomed crops (reference / each configuration / error map), machine and build info. Relative
// links only, no scripts or network: it opens from disk.
#pragma once
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

std::string machine_description();  // CPU model and cores from /proc/cpuinfo
std::string build_description();     // version, compiler, build type

void write_report(const std::string& out_dir, const Study& s, const std::vector<Row>& rows,
                  const std::vector<ReportConfig>& configs, const std::vector<PlotResult>& plots, const ReportInfo& info);

}  // namespace rl::study
