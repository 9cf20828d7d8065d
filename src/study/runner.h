// `restir study`: runs every (scene x configuration x seed) of a study that DIR/results.json does
// not hold yet, then rewrites plots and report.html from all rows.
//
// Output folder DIR:
//   results.json, results.csv   one row per (configuration, seed) [x frame for over-time studies]
//   references/<hash>.exr       converged path-traced references (shared by reruns)
//   renders/<id>.exr            the last frame of every (configuration, seed) (for noise)
//   images/<config>*.{exr,png}  first seed of each configuration: EXR, PNG, error map, crops
//   plots/<name>.{png,svg,gp,dat}
//   report.html
#pragma once
#include <string>

namespace rl::study {

struct StudyArgs {
  std::string study;  // name of a built-in study or path to a JSON file
  std::string out;
  bool quick = false;
  int jobs = 1;
  bool quiet = false;
};

// Returns the exit status (0, or 130 when interrupted by SIGINT/SIGTERM). Throws on errors.
int run_study(const StudyArgs& args);

}  // namespace rl::study
