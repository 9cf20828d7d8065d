// `restir study`: runs every (scene x configuration x seed) of a study that DIR/results.json does
// not hold yet, then rewrites plots and report.html from all rows.
//
// Output folder DIR:
//   results.json, results.csv   one row per (configuration, seed) [x frame for over-time studies]
//   references/<hash>.exr       converged path-traced references (shared by reruns)
//   locks/<hash>.lock           fcntl locks: one process renders each reference (shards.h)
//   shards/I-of-N/results.*     rows of shard I of N (--shard), gathered by --merge
//   slurm/                      job scripts and logs of --slurm
//   renders/<id>.exr            the last frame of every (configuration, seed) (for noise)
//   images/<config>*.{exr,png}  first seed of each configuration: EXR, PNG, error map, crops
//   plots/<name>.{png,svg,gp,dat}
//   report.html
#pragma once
#include <string>
#include <vector>

#include "study/shards.h"

namespace rl::study {

// What a study still has to compute: filled instead of rendering when StudyArgs::plan is set.
struct StudyPlan {
  size_t jobs = 0;                   // jobs of the study (scenes x configurations x seeds, duplicates removed)
  std::vector<size_t> missing;       // positions (shards.h) of the jobs no store holds yet
};

struct StudyArgs {
  std::string study;  // name of a built-in study or path to a JSON file
  std::string out;
  bool quick = false;
  // --set KEY=VALUE: options over the study's base for every configuration (and, for render.*
  // keys such as render.backend, its references): a study run on the GPU with
  // --set render.backend=cuda. An axis of the same key still sweeps it.
  std::vector<std::string> sets;
  int jobs = 1;
  bool quiet = false;
  ShardSpec shard;     // --shard I/N: run only shard I's jobs, rows into DIR/shards/I-of-N (shards.h)
  bool merge = false;  // --merge: run nothing; gather the main store and every shard into the report
  StudyPlan* plan = nullptr;  // set: validate everything, fill *plan and return 0 without rendering
};

// Returns the exit status (0; 130 when interrupted by SIGINT/SIGTERM; 1 when --merge finds jobs
// that no part holds, after writing the report of those it has). Throws on errors.
int run_study(const StudyArgs& args);

}  // namespace rl::study
