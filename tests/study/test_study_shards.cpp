// Sharded studies (issue 14) without a cluster: shards run as separate processes at the same time
// into one folder, --merge gathers them and equals a one-process run; a missing shard is named.
// The Slurm path itself is tested by tests/study/slurm_study.sh on a private one-node cluster.
#include <doctest/doctest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <future>
#include <sstream>
#include <vector>

#include "study/shards.h"
#include "study/slurm.h"
#include "study/study_file.h"
#include "test_helpers.h"

using namespace rl;
using namespace rl::test;
namespace fs = std::filesystem;

namespace {
// results.csv without the timing columns, which differ between runs.
std::vector<std::string> deterministic_rows(const fs::path& csv) {
  std::ifstream in(csv);
  std::vector<std::string> rows;
  std::vector<bool> keep;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
    if (keep.empty())
      for (const auto& c : cells) keep.push_back(c != "ms_median" && c != "ms_iqr" && c != "fps");
    std::string row;
    for (size_t i = 0; i < cells.size() && i < keep.size(); ++i)
      if (keep[i]) row += cells[i] + ",";
    rows.push_back(row);
  }
  return rows;
}
}  // namespace

TEST_SUITE("study_shards") {
  TEST_CASE("--shard I/N parses strictly; the array spec lists only shards that own missing jobs") {
    CHECK(study::parse_shard("2/4").index == 2);
    CHECK(study::parse_shard("2/4").count == 4);
    for (const char* bad : {"4/4", "-1/4", "1/0", "1", "a/4", "1/4x", "/4", ""}) {
      CAPTURE(bad);
      CHECK_THROWS_AS(study::parse_shard(bad), study::StudyError);
    }
    study::ShardSpec s = study::parse_shard("1/3");
    CHECK(s.owns(1));
    CHECK(s.owns(4));
    CHECK(!s.owns(0));
    study::StudyPlan plan;
    plan.jobs = 6;
    plan.missing = {0, 1, 2, 3, 4, 5};
    CHECK(study::slurm_array_spec(plan, 4) == "0-3");
    plan.missing = {3};
    CHECK(study::slurm_array_spec(plan, 4) == "3");
    plan.missing = {1, 5, 2};
    CHECK(study::slurm_array_spec(plan, 4) == "1,2");
    plan.missing.clear();
    CHECK(study::slurm_array_spec(plan, 4).empty());
  }

  TEST_CASE("the job scripts run the shards and the merge of the same study, folder and options") {
    study::StudyArgs a;
    a.study = "candidates";
    a.out = "/data/run 1";
    a.quick = true;
    study::SlurmArgs sl;
    sl.shards = 8;
    sl.partition = "short";
    sl.time = "1:00:00";
    sl.cpus = 4;
    const std::string shard = study::slurm_shard_script(a, sl, "/opt/restir");
    CHECK(shard.find("#SBATCH --partition=short\n") != std::string::npos);
    CHECK(shard.find("#SBATCH --time=1:00:00\n") != std::string::npos);
    CHECK(shard.find("#SBATCH --cpus-per-task=4\n") != std::string::npos);
    sl.sbatch_args = {"--account=proj1", "--gres=gpu:1"};
    const std::string extra = study::slurm_shard_script(a, sl, "/opt/restir");
    CHECK(extra.find("#SBATCH --account=proj1\n#SBATCH --gres=gpu:1\n") != std::string::npos);
    CHECK(study::slurm_merge_script(a, sl, "/opt/restir").find("#SBATCH --account=proj1\n") != std::string::npos);
    sl.sbatch_args = {"--mem=1G\nrm -rf /"};
    CHECK_THROWS_AS(study::slurm_shard_script(a, sl, "/opt/restir"), study::StudyError);
    sl.sbatch_args.clear();
    CHECK(shard.find("exec '/opt/restir' study 'candidates' --out '/data/run 1' --shard \"${SLURM_ARRAY_TASK_ID}/8\" --jobs 1 --quick\n") !=
          std::string::npos);
    const std::string merge = study::slurm_merge_script(a, sl, "/opt/restir");
    CHECK(merge.find("exec '/opt/restir' study 'candidates' --out '/data/run 1' --merge --quick\n") != std::string::npos);
    a.sets = {"render.backend=cuda", "di.spatial_radius=5"};  // every task runs the same configurations
    CHECK(study::slurm_shard_script(a, sl, "/opt/restir").find("--quick --set 'render.backend=cuda' --set 'di.spatial_radius=5'\n") !=
          std::string::npos);
    CHECK(study::slurm_merge_script(a, sl, "/opt/restir").find("--merge --quick --set 'render.backend=cuda' --set 'di.spatial_radius=5'\n") !=
          std::string::npos);
  }

  TEST_CASE("four shards run at once into one folder; --merge equals a one-process run and names missing jobs") {
    const fs::path d = fs::temp_directory_path() / ("restir-shards-" + std::to_string(::getpid()));
    fs::remove_all(d);
    const std::string study = "study candidates --quick -q --out ";
    REQUIRE(run_restir(study + (d / "local").string()).status == 0);

    // Shards 0-2 at the same time (they share references/ under its lock), then merge: shard 3's
    // job is missing, named, and the exit status says so.
    const std::string out = (d / "sharded").string();
    std::vector<std::future<CommandResult>> shards;
    for (int i = 0; i < 3; ++i)
      shards.push_back(std::async(std::launch::async, [&, i] { return run_restir(study + out + " --shard " + std::to_string(i) + "/4"); }));
    for (auto& f : shards) {
      CommandResult r = f.get();
      INFO(r.output);
      CHECK(r.status == 0);
    }
    CHECK(!fs::exists(d / "sharded/results.csv"));  // shards write only their own stores
    for (int i = 0; i < 3; ++i) CHECK(fs::exists(d / "sharded/shards" / (std::to_string(i) + "-of-4") / "results.csv"));
    CommandResult partial = run_restir("study candidates --quick --out " + out + " --merge");
    INFO(partial.output);
    CHECK(partial.status == 1);
    CHECK(partial.output.find("error: --merge: 1 of 6 job(s) missing from every shard") != std::string::npos);

    // The last shard, then the merge: the same rows and deterministic metrics as one process.
    CommandResult last = run_restir("study candidates --quick --out " + out + " --shard 3/4");
    INFO(last.output);
    CHECK(last.output.find("shard 3/4: 1 job(s) run") != std::string::npos);
    CHECK(run_restir(study + out + " --merge").status == 0);
    CHECK(deterministic_rows(d / "sharded/results.csv") == deterministic_rows(d / "local/results.csv"));
    CHECK(deterministic_rows(d / "local/results.csv").size() == 7);  // header + 6 jobs
    // Rerunning a shard finds its jobs done (in its store or any other): nothing runs.
    CHECK(run_restir("study candidates --quick --out " + out + " --shard 0/4").output.find("0 to run") != std::string::npos);
    // Misuse is a usage error.
    CHECK(run_restir(study + out + " --shard 0/4 --merge").status != 0);
    CHECK(run_restir(study + out + " --dry-run").status == 2);
    fs::remove_all(d);
  }
}
