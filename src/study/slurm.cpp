#include "study/slurm.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <set>

#include <fmt/format.h>

#include "image/image_io.h"
#include "study/study_file.h"

namespace rl::study {
namespace fs = std::filesystem;

namespace {

// A single-quoted shell word ('a'\''b' for a quote inside).
std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string absolute(const std::string& p) { return fs::absolute(fs::path(p)).lexically_normal().string(); }

// A study given as a file is passed to the tasks by absolute path (they may start elsewhere).
std::string study_word(const StudyArgs& a) { return fs::exists(a.study) ? absolute(a.study) : a.study; }
// The flags every task repeats so that it runs the same study: --quick and each --set.
std::string study_flags(const StudyArgs& a) {
  std::string f = a.quick ? " --quick" : "";
  for (const std::string& kv : a.sets) f += " --set " + shell_quote(kv);
  return f;
}

std::string header(const SlurmArgs& sl, const std::string& name, const std::string& log) {
  std::string h = "#!/bin/bash\n";
  h += "#SBATCH --job-name=" + name + "\n";
  h += "#SBATCH --output=" + log + "\n";
  h += fmt::format("#SBATCH --cpus-per-task={}\n", sl.cpus);
  if (!sl.partition.empty()) h += "#SBATCH --partition=" + sl.partition + "\n";
  if (!sl.time.empty()) h += "#SBATCH --time=" + sl.time + "\n";
  for (const std::string& arg : sl.sbatch_args) {
    // One sbatch option per line: a newline would start a shell command in the script.
    if (!arg.starts_with("-") || arg.find_first_of("\n\r") != std::string::npos)
      throw StudyError("--sbatch-arg '" + arg + "': expected one sbatch option such as --account=NAME, --mem=8G or --gres=gpu:1");
    h += "#SBATCH " + arg + "\n";
  }
  return h;
}

std::string slurm_dir(const StudyArgs& a) { return (fs::path(absolute(a.out)) / "slurm").string(); }

// Runs `command`, returns its stdout; throws StudyError with its output when it fails.
std::string run_command(const std::string& command) {
  std::string output;
  FILE* p = ::popen((command + " 2>&1").c_str(), "r");
  if (!p) throw StudyError("--slurm: cannot run " + command);
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) output.append(buf, n);
  const int status = ::pclose(p);
  while (!output.empty() && (output.back() == '\n' || output.back() == '\r')) output.pop_back();
  if (status != 0) throw StudyError("--slurm: `" + command + "` failed: " + output);
  return output;
}

std::string job_id_of(const std::string& parsable) { return parsable.substr(0, parsable.find(';')); }

}  // namespace

std::string slurm_shard_script(const StudyArgs& a, const SlurmArgs& sl, const std::string& binary) {
  const std::string dir = slurm_dir(a);
  std::string s = header(sl, "restir-study", dir + "/logs/shard-%A_%a.out");
  s += fmt::format("# Written by `restir study --slurm`: array task i runs shard i of {} (restir study --shard).\n", sl.shards);
  s += "set -euo pipefail\n";
  s += fmt::format("exec {} study {} --out {} --shard \"${{SLURM_ARRAY_TASK_ID}}/{}\" --jobs 1{}\n", shell_quote(binary),
                   shell_quote(study_word(a)), shell_quote(absolute(a.out)), sl.shards, study_flags(a));
  return s;
}

std::string slurm_merge_script(const StudyArgs& a, const SlurmArgs& sl, const std::string& binary) {
  const std::string dir = slurm_dir(a);
  std::string s = header(sl, "restir-merge", dir + "/logs/merge-%j.out");
  s += "# Written by `restir study --slurm`: gathers the shards into results.csv, plots and report.html.\n";
  s += "set -euo pipefail\n";
  s += fmt::format("exec {} study {} --out {} --merge{}\n", shell_quote(binary), shell_quote(study_word(a)),
                   shell_quote(absolute(a.out)), study_flags(a));
  return s;
}

std::string slurm_array_spec(const StudyPlan& plan, int shards) {
  std::set<int> owners;
  for (size_t p : plan.missing) owners.insert(int(p % size_t(shards)));
  if (int(owners.size()) == shards) return fmt::format("0-{}", shards - 1);
  std::string spec;
  for (int i : owners) {
    if (!spec.empty()) spec += ',';
    spec += std::to_string(i);
  }
  return spec;
}

int submit_study_slurm(const StudyArgs& a, const SlurmArgs& sl) {
  if (sl.shards < 1) throw StudyError("--shards must be >= 1");
  if (sl.cpus < 1) throw StudyError("--cpus must be >= 1");
  StudyPlan plan;
  StudyArgs planning = a;
  planning.plan = &plan;
  run_study(planning);  // validates the study and finds what is missing; renders nothing
  char self[4096];
  const ssize_t len = ::readlink("/proc/self/exe", self, sizeof self - 1);
  const std::string binary = len > 0 ? std::string(self, size_t(len)) : std::string("restir");
  const std::string dir = slurm_dir(a);
  const std::string shard_script = slurm_shard_script(a, sl, binary), merge_script = slurm_merge_script(a, sl, binary);
  const std::string array = slurm_array_spec(plan, sl.shards);
  const std::string array_cmd = "sbatch --parsable --array=" + array + " " + shell_quote(dir + "/shard.sbatch");
  auto merge_cmd = [&](const std::string& after) {
    return (after.empty() ? std::string("sbatch --parsable ") : "sbatch --parsable --kill-on-invalid-dep=yes --dependency=afterok:" + after + " ") +
           shell_quote(dir + "/merge.sbatch");
  };
  if (sl.dry_run) {
    fmt::print("# {}/shard.sbatch\n{}\n# {}/merge.sbatch\n{}\n", dir, shard_script, dir, merge_script);
    fmt::print("# {} of {} job(s) missing\n", plan.missing.size(), plan.jobs);
    if (!array.empty()) fmt::print("{}\n", array_cmd);
    fmt::print("{}\n", merge_cmd(array.empty() ? "" : "ARRAY_JOB_ID"));
    return 0;
  }
  if (run_command("command -v sbatch || echo missing").ends_with("missing"))
    throw StudyError("--slurm: sbatch not found; it needs Slurm's client tools and a cluster (Debian slurm-client; "
                     "scripts/slurm-local.sh start runs a one-node cluster here)");
  fs::create_directories(fs::path(dir) / "logs");
  write_text_file_atomic(dir + "/shard.sbatch", shard_script);
  write_text_file_atomic(dir + "/merge.sbatch", merge_script);
  std::string array_job;
  if (!array.empty()) array_job = job_id_of(run_command(array_cmd));
  const std::string merge_job = job_id_of(run_command(merge_cmd(array_job)));
  if (array.empty())
    fmt::print("all {} job(s) done already: submitted only the merge, job {}\n", plan.jobs, merge_job);
  else
    fmt::print("submitted array job {} (shards {} of {}, {} of {} job(s) missing) and merge job {} (runs when all "
               "succeed); logs in {}/logs\n", array_job, array, sl.shards, plan.missing.size(), plan.jobs, merge_job, dir);
  return 0;
}

}  // namespace rl::study
