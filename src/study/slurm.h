// `restir study NAME --out DIR --slurm`: runs a study as a Slurm job array (issue 14). Writes
// DIR/slurm/shard.sbatch (task i runs `restir study NAME --out DIR --shard i/N`) and
// DIR/slurm/merge.sbatch (`--merge`), submits the array with `sbatch --array=...` for the shards
// that still have missing jobs, and the merge with `--dependency=afterok:ARRAY`. Resubmitting after
// failed or cancelled tasks submits only the shards with missing jobs, and they run only those.
#pragma once
#include <string>

#include "study/runner.h"

namespace rl::study {

struct SlurmArgs {
  int shards = 4;         // N: array tasks
  std::string partition;  // sbatch --partition (empty: the cluster's default)
  std::string time;       // sbatch --time (empty: the partition's default)
  int cpus = 1;           // sbatch --cpus-per-task; each task renders with that many threads
  bool dry_run = false;   // print the scripts and the sbatch commands; write and submit nothing
  // Further sbatch options, each one "#SBATCH" line in both scripts (--account=proj, --mem=8G,
  // --gres=gpu:1): what a cluster asks that the flags above do not name.
  std::vector<std::string> sbatch_args;
};

// The job scripts (exposed for tests). `binary` is the restir executable the tasks run.
std::string slurm_shard_script(const StudyArgs& a, const SlurmArgs& sl, const std::string& binary);
std::string slurm_merge_script(const StudyArgs& a, const SlurmArgs& sl, const std::string& binary);
// "0-3" / "1,3": the array indices of the shards (of sl.shards) that own a missing job.
std::string slurm_array_spec(const StudyPlan& plan, int shards);

// Returns the exit status. Throws StudyError when sbatch is missing or refuses the job.
int submit_study_slurm(const StudyArgs& a, const SlurmArgs& sl);

}  // namespace rl::study
