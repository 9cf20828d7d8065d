#include "study/runner.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <thread>
#include <tuple>

#include <fmt/format.h>

#include "core/build_info.h"
#include "image/image_io.h"
#include "image/metrics.h"
#include "frame/integrator.h"
#include "frame/render.h"
#include "scene/loader.h"
#include "study/images.h"
#include "study/masks.h"
#include "study/plots.h"
#include "study/references.h"
#include "study/report.h"
#include "study/results.h"
#include "study/scorer.h"
#include "study/study_file.h"

namespace rl::study {
namespace fs = std::filesystem;

namespace {

std::atomic<bool> g_interrupted{false};

extern "C" void on_signal(int sig) {
  g_interrupted = true;
  std::signal(sig, SIG_DFL);  // a second signal ends the process at once
}

struct SceneData {
  std::string as_written, path, text;
  std::string inputs_hash;  // content of every file the scene was read from + the binary's version
  Scene scene;
  Options defaults;  // defaults < scene hints
};

struct Job {
  size_t index = 0;
  size_t scene = 0, config = 0;
  uint64_t seed = 0;
  size_t seed_index = 0;  // position of seed in the study's list (0: the job that writes the images)
  Options options;
  std::string id, config_id;
  std::vector<ReferenceJob> refs;  // per frame (moving camera or animated scene) or one (static)
};

std::string read_text(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Everything outside the options that determines a row: the contents of the scene file and of
// every file it reads (includes, meshes, textures, env maps), and the renderer's version. Part of
// each row's id, so editing a scene makes its old rows stale (recomputed), never silently reused.
std::string inputs_hash(const Scene& scene, const std::string& path) {
  std::string text = std::string("version=") + build_id();
  std::vector<std::string> files = scene.input_files;
  if (files.empty()) files.push_back(path);
  for (const std::string& f : files) text += "\nfile " + f + " " + hash_hex(read_text(f));
  return hash_hex(text);
}

// What a row computes, without the inputs' contents: its scene as written, seed and options.
std::string row_key(const std::string& scene, uint64_t seed, std::vector<std::pair<std::string, std::string>> opts) {
  std::erase_if(opts, [](const auto& kv) { return kv.first == "render.threads"; });
  std::string k = scene + "|" + std::to_string(seed);
  for (const auto& [a, b] : opts) k += "|" + a + "=" + b;
  return k;
}

// Ids of the stored rows for the same scene, seed and options as a current job but another id:
// computed from inputs that have changed since. Each is dropped once a row of the current inputs
// replaces it (never before: a --merge or a shard that recomputes nothing keeps the old data).
std::set<std::string> stale_ids(const std::vector<Row>& stored, const std::vector<Job>& jobs,
                                const std::vector<SceneData>& scenes) {
  const auto key = row_key;
  std::set<std::string> ids, current;
  for (const Job& j : jobs) {
    ids.insert(j.id);
    current.insert(key(scenes[j.scene].as_written, j.seed, option_values(j.options)));
  }
  std::set<std::string> stale;
  for (const Row& r : stored)
    if (!ids.count(r.id) && current.count(key(r.scene, r.seed, r.options))) stale.insert(r.id);
  return stale;
}

// The identity of a configuration: every option except the thread count (which does not change
// the image) plus the scene as written in the study. Only values that differ from the defaults
// enter, so that options added to the renderer later do not change the ids of existing rows.
std::string option_identity(Options o, const std::string& scene) {
  o.render.threads = 0;
  return non_default_options(o) + "scene=" + scene;
}

class Progress {
 public:
  // On a terminal a bar redrawn in place; elsewhere (a log file, a Slurm log) one plain line per job,
  // so that a long study is not silent and its log holds no escape codes.
  Progress(size_t total, bool enabled) : total_(total), enabled_(enabled), bar_(enabled && isatty(STDERR_FILENO)) {}
  void step(const std::string& what) {
    std::lock_guard lock(mutex_);
    ++done_;
    if (!enabled_) return;
    double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    double f = total_ ? double(done_) / double(total_) : 1;
    int filled = int(f * 30);
    double eta = done_ ? el * double(total_ - done_) / double(done_) : 0;
    if (bar_)
      std::fprintf(stderr, "\r\033[K[%.*s%*s] %zu/%zu  %s  ETA %.0fs", filled, "##############################", 30 - filled,
                   "", done_, total_, what.c_str(), eta);
    else
      std::fprintf(stderr, "job %zu/%zu done: %s (%.0f s elapsed, ETA %.0f s)\n", done_, total_, what.c_str(), el, eta);
    std::fflush(stderr);
  }
  void finish() {
    if (bar_) std::fprintf(stderr, "\n");
  }

 private:
  size_t total_, done_ = 0;
  bool enabled_, bar_;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

void remove_stale_temp_files(const fs::path& dir) {
  if (!fs::exists(dir)) return;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file() && e.path().filename().string().find(".tmp-") != std::string::npos) fs::remove(e.path());
}

std::vector<Row> run_job(const Study& s, const Job& job, const SceneData& sd, ReferenceCache& refs,
                         const std::string& out) {
  const Options& o = job.options;
  std::vector<std::pair<const Image*, double>> references;
  for (const auto& r : job.refs) {
    const Image* image = &refs.get(r, sd.scene);  // first: loading a reference reads its own error too
    references.emplace_back(image, refs.own_error(r.key));
  }
  RunScorer scorer(s, o, sd.scene, {job.id, job.config_id, sd.as_written, job.seed}, std::move(references));
  // What is scored: the frame after the post-process stage when there is one (the denoiser's
  // output against the integrator's reference), else the integrator's raw frame.
  const bool denoised = o.denoise.method != DenoiseMethod::none;
  double frame_ms = 0;
  RenderHooks hooks;
  hooks.on_frame = [&](int f, const Image& img, double ms) {
    frame_ms = ms;  // the whole frame: the integrator, the AOVs and the denoiser (render_frame)
    if (!denoised) scorer.frame(f, img, ms);
  };
  if (denoised) hooks.on_denoised = [&](int f, const Image& img) { scorer.frame(f, img, frame_ms); };
  RenderResult res = render(sd.scene, o, hooks);
  const Image& final_image = denoised ? res.denoised : res.last;
  scorer.last_frame(final_image, res.frame_ms);
  scorer.cost(res.frame_stages, res.buffer_bytes);
  const Image* last_ref = scorer.ref_of(o.render.frames - 1);
  // The last frame of every seed, for the noise across seeds.
  if (s.has_metric("noise")) write_exr((fs::path(out) / "renders" / (job.id + ".exr")).string(), final_image);
  if (job.seed_index == 0) {
    const std::string prefix = (fs::path(out) / "images" / job.config_id).string();
    write_config_images(prefix, final_image, last_ref, o.output);
    if (last_ref) write_config_images((fs::path(out) / "images" / ("ref-" + job.config_id)).string(), *last_ref, nullptr, o.output, false);
  }
  return std::move(scorer.rows);
}

// The jobs of a study, validated before the first render.
struct JobPlan {
  std::vector<Job> jobs;
  std::vector<ReportConfig> report_configs;  // one per configuration: its first seed's job
};

// What this process does with the jobs, given what the stores hold already.
struct Work {
  std::vector<Row> known;           // rows of the main store and of every shard's
  std::vector<const Job*> pending;  // to run here
  std::vector<const Job*> missing;  // --merge: jobs that no store holds
  std::set<std::string> stale;      // ids of stored rows computed from older inputs
};

void prepare_out_dir(const StudyArgs& a, const fs::path& out) {
  if (!a.plan)  // a plan (--slurm, its --dry-run) writes nothing
    for (const char* d : {"", "references", "renders", "images", "plots"}) fs::create_directories(out / d);
  if (a.shard.active() && a.merge) throw StudyError("--shard and --merge exclude each other: merge once all shards ran");
  // Temporary files of an interrupted run. Shards share DIR with other running shards: each only
  // clears its own store's folder, never another process's files in flight.
  if (a.plan) {
  } else if (a.shard.active()) {
    fs::create_directories(shard_dir(a.out, a.shard));
    remove_stale_temp_files(shard_dir(a.out, a.shard));
  } else if (!a.merge) {
    remove_stale_temp_files(out);
  }
}

std::vector<SceneData> load_scenes(const Study& s) {
  std::vector<SceneData> scenes(s.scenes.size());
  for (size_t i = 0; i < s.scenes.size(); ++i) {
    scenes[i].as_written = s.scenes[i];
    scenes[i].path = s.scene_paths[i];
    scenes[i].text = read_text(s.scene_paths[i]);
    scenes[i].scene = load_scene(s.scene_paths[i]);
    scenes[i].inputs_hash = inputs_hash(scenes[i].scene, s.scene_paths[i]);
    apply_scene_hints(scenes[i].defaults, scenes[i].scene.hints);
  }
  return scenes;
}

// The part of a job's ids that its options do not say: the scene's inputs and the camera path's
// content too, which determines the images like the scene's files do.
std::string job_inputs(const SceneData& sd, const Options& o) {
  const std::string& cam = o.render.camera_path;
  return " inputs=" + sd.inputs_hash + (cam.empty() ? "" : " camera=" + hash_hex(read_text(cam)));
}

void describe_references(const Study& s, const SceneData& sd, ReferenceCache& refs, Job& j) {
  if (!s.needs_reference()) return;
  if (s.per_frame() && sequence_moves(sd.scene, j.options)) {
    for (int f = 0; f < s.frames; ++f)
      j.refs.push_back(refs.describe(s, sd.scene, sd.as_written, sd.text + "\ninputs=" + sd.inputs_hash, sd.defaults, j.options, f));
  } else {
    j.refs.push_back(refs.describe(s, sd.scene, sd.as_written, sd.text + "\ninputs=" + sd.inputs_hash, sd.defaults, j.options, s.frames - 1));
  }
}

JobPlan plan_jobs(const Study& s, const std::string& file, const std::vector<SceneData>& scenes,
                  const std::vector<Configuration>& configs, ReferenceCache& refs) {
  JobPlan plan;
  std::vector<Job>& jobs = plan.jobs;
  for (size_t si = 0; si < scenes.size(); ++si)
    for (size_t ci = 0; ci < configs.size(); ++ci) {
      for (size_t k = 0; k < s.seeds.size(); ++k) {
        Job j;
        j.index = jobs.size();
        j.scene = si;
        j.config = ci;
        j.seed = s.seeds[k];
        j.seed_index = k;
        try {
          j.options = make_options(s, scenes[si].defaults, configs[ci], j.seed);
        } catch (const std::exception& e) {
          throw StudyError(fmt::format("{}: scene {}: {}", file, s.scenes[si], e.what()));
        }
        find_integrator(j.options.integrator);
        const std::string inputs = job_inputs(scenes[si], j.options);
        j.id = hash_hex(option_identity(j.options, s.scenes[si]) + inputs);
        if (std::any_of(jobs.begin(), jobs.end(), [&](const Job& o) { return o.id == j.id; })) continue;  // duplicate values
        Options no_seed = j.options;
        no_seed.render.seed = 0;
        j.config_id = hash_hex(option_identity(no_seed, s.scenes[si]) + inputs);
        describe_references(s, scenes[si], refs, j);
        if (j.seed_index == 0) plan.report_configs.push_back({j.config_id, s.scenes[si], configs[ci].values, !j.refs.empty()});
        jobs.push_back(std::move(j));
      }
    }
  return plan;
}

// Done: a row in the main store or in any shard's (a job may have run in an earlier array).
std::vector<Row> known_rows(const StudyArgs& a, const Study& s, const std::vector<std::string>& columns,
                            const ResultStore& store) {
  std::vector<Row> known = load_shard_rows(a.out, columns, s.name);
  if (a.shard.active()) {
    ResultStore main_store(a.out, s.name, columns);
    main_store.load();
    return union_rows(main_store.rows(), known);
  }
  return union_rows(store.rows(), known);
}

void fill_plan(StudyPlan& plan, const std::vector<Job>& jobs, const std::set<std::string>& done) {
  plan.jobs = jobs.size();
  plan.missing.clear();
  for (size_t p = 0; p < jobs.size(); ++p)
    if (!done.count(jobs[p].id)) plan.missing.push_back(p);
}

void select_jobs(const StudyArgs& a, const std::vector<Job>& jobs, const std::set<std::string>& done, Work& w) {
  for (size_t p = 0; p < jobs.size(); ++p) {
    if (done.count(jobs[p].id)) continue;
    if (a.merge) w.missing.push_back(&jobs[p]);
    else if (a.shard.owns(p)) w.pending.push_back(&jobs[p]);
  }
  // Run order: per scene, seed by seed, every configuration of a seed in turn. A shared machine's
  // load drifts over minutes; run configuration by configuration, that drift would land on whole
  // configurations and read as a difference in frame time between them. Interleaved, it spreads
  // over all of them, and the paired (same-seed) comparisons see neighbouring runs.
  std::stable_sort(w.pending.begin(), w.pending.end(), [](const Job* x, const Job* y) {
    return std::tie(x->scene, x->seed_index, x->config) < std::tie(y->scene, y->seed_index, y->config);
  });
}

std::vector<const ReferenceJob*> references_to_render(const std::vector<const Job*>& pending, const ReferenceCache& refs) {
  std::vector<const ReferenceJob*> ref_todo;
  std::set<std::string> ref_keys;
  for (const Job* j : pending)
    for (const auto& r : j->refs)
      if (ref_keys.insert(r.key).second && !refs.on_disk(r.key)) ref_todo.push_back(&r);
  return ref_todo;
}

void render_references(const std::vector<const ReferenceJob*>& ref_todo, const std::vector<const Job*>& pending,
                       const std::vector<SceneData>& scenes, ReferenceCache& refs, Progress& progress) {
  for (const ReferenceJob* r : ref_todo) {
    if (g_interrupted) break;
    const Job* owner = nullptr;
    for (const Job* j : pending)
      for (const auto& rr : j->refs)
        if (&rr == r) owner = j;
    refs.get(*r, scenes[owner->scene].scene);
    progress.step("reference " + r->key.substr(0, 8));
  }
}

// Runs the pending jobs on `threads` threads until all ran, one failed or a signal came; returns
// the first job's exception (null when none failed).
std::exception_ptr run_jobs(const Study& s, const std::vector<const Job*>& pending,
                            const std::vector<SceneData>& scenes, ReferenceCache& refs, ResultStore& store,
                            Progress& progress, int threads, const fs::path& out) {
  std::atomic<size_t> next{0};
  std::mutex error_mutex;
  std::exception_ptr error;
  auto worker = [&] {
    for (;;) {
      if (g_interrupted) return;
      {
        std::lock_guard lock(error_mutex);
        if (error) return;
      }
      size_t i = next++;
      if (i >= pending.size()) return;
      const Job& j = *pending[i];
      try {
        std::vector<Row> rows = run_job(s, j, scenes[j.scene], refs, out.string());
        store.append(rows);
        progress.step(fmt::format("{} seed {}", s.scenes[j.scene], j.seed));
      } catch (const std::exception&) {
        std::lock_guard lock(error_mutex);
        if (!error) error = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < std::min<int>(threads, int(pending.size())); ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  return error;
}

// The references, then the jobs, with SIGINT and SIGTERM caught: they stop both between items
// (g_interrupted) so that what ran is saved. Rethrows the first job's error.
void render_all(const StudyArgs& a, const Study& s, const std::vector<SceneData>& scenes, ReferenceCache& refs,
                const std::vector<const ReferenceJob*>& ref_todo, const std::vector<const Job*>& pending,
                ResultStore& store) {
  g_interrupted = false;
  auto old_int = std::signal(SIGINT, on_signal);
  auto old_term = std::signal(SIGTERM, on_signal);
  Progress progress(ref_todo.size() + pending.size(), !a.quiet);
  render_references(ref_todo, pending, scenes, refs, progress);
  const std::exception_ptr error = run_jobs(s, pending, scenes, refs, store, progress, a.jobs, fs::path(a.out));
  progress.finish();
  std::signal(SIGINT, old_int);
  std::signal(SIGTERM, old_term);
  if (error) std::rethrow_exception(error);  // as the job threw it: its own type and message
}

// Drops the stale rows that a row of the current inputs replaces (what they compute is computed again).
void drop_replaced_rows(std::vector<Row>& rows, const std::map<std::string, size_t>& order,
                        const std::set<std::string>& stale) {
  std::set<std::string> recomputed;  // what the rows of the current inputs compute
  for (const Row& r : rows)
    if (order.count(r.id)) recomputed.insert(row_key(r.scene, r.seed, r.options));
  std::erase_if(rows, [&](const Row& r) { return stale.count(r.id) > 0 && recomputed.count(row_key(r.scene, r.seed, r.options)); });
}

void add_noise(const Study& s, const std::vector<Job>& jobs, const std::map<std::string, size_t>& order,
               const fs::path& out, std::vector<Row>& rows) {
  std::map<std::string, std::vector<std::string>> seeds_of_config;
  for (const auto& j : jobs) seeds_of_config[j.config_id].push_back(j.id);
  std::map<std::string, double> noise;
  for (const auto& [cfg, ids] : seeds_of_config) {
    std::vector<Image> imgs;
    for (const auto& id : ids) {
      fs::path p = out / "renders" / (id + ".exr");
      if (fs::exists(p)) imgs.push_back(read_image(p.string()));
    }
    noise[cfg] = noise_across(imgs);
  }
  for (auto& r : rows) {
    if (!order.count(r.id)) continue;  // a row of older inputs or another study version keeps its value
    auto it = noise.find(r.config);
    bool last = r.frame == s.frames - 1;
    r.metrics["noise"] = it != noise.end() && last ? it->second : kNone;
  }
}

void write_plots_and_report(const StudyArgs& a, const Study& s, const JobPlan& plan, const Work& w,
                            const std::vector<Row>& current, const ReferenceCache& refs,
                            std::chrono::steady_clock::time_point t_start) {
  const fs::path out(a.out);
  std::vector<PlotResult> plots = write_plots(s, current, (out / "plots").string(), a.quick);
  for (const auto& p : plots)
    if (!p.drawn) std::fprintf(stderr, "warning: plot %s not drawn: %s\n", p.name.c_str(), p.message.c_str());
  ReportInfo info;
  info.jobs = a.jobs;
  info.quick = a.quick;
  info.references_rendered = refs.rendered();
  info.references_reused = refs.reused();
  info.jobs_run = w.pending.size();
  info.jobs_total = plan.jobs.size();
  info.stale_rows = w.stale.size();
  info.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  write_report(out.string(), s, current, plan.report_configs, plots, info);
}

// --merge: names the first few jobs that no store holds. Returns the exit status.
int report_missing(const Study& s, const std::vector<const Job*>& missing, size_t jobs) {
  if (missing.empty()) return 0;
  std::string list;
  for (size_t i = 0; i < missing.size() && i < 5; ++i)
    list += fmt::format("{}{} seed {} ({})", i ? ", " : "", s.scenes[missing[i]->scene], missing[i]->seed, missing[i]->id);
  std::fprintf(stderr, "error: --merge: %zu of %zu job(s) missing from every shard: %s%s; resubmit (--slurm runs only the missing ones) or run the study here without --merge\n",
               missing.size(), jobs, list.c_str(), missing.size() > 5 ? ", ..." : "");
  return 1;
}

// Final pass: noise across seeds, rows in job order, plots, report.
int finish_study(const StudyArgs& a, const Study& s, const JobPlan& plan, const Work& w, ResultStore& store,
                 const ReferenceCache& refs, std::chrono::steady_clock::time_point t_start) {
  const fs::path out(a.out);
  const std::vector<Job>& jobs = plan.jobs;
  std::map<std::string, size_t> order;
  for (const auto& j : jobs) order[j.id] = j.index;
  std::vector<Row> rows = union_rows(store.rows(), w.known);
  drop_replaced_rows(rows, order, w.stale);
  if (s.has_metric("noise")) add_noise(s, jobs, order, out, rows);
  std::stable_sort(rows.begin(), rows.end(), [&](const Row& x, const Row& y) {
    auto ix = order.count(x.id) ? order[x.id] : jobs.size(), iy = order.count(y.id) ? order[y.id] : jobs.size();
    return ix != iy ? ix < iy : x.frame < y.frame;
  });
  // Rows of configurations that are no longer in the study stay in the files but not in plots.
  store.replace(rows);
  std::vector<Row> current;
  for (const auto& r : rows)
    if (order.count(r.id)) current.push_back(r);
  write_plots_and_report(a, s, plan, w, current, refs, t_start);
  if (!a.quiet)
    std::fprintf(stderr, "done: %zu row(s), %d reference(s) rendered, %d reused; %s\n", rows.size(), refs.rendered(),
                 refs.reused(), (out / "report.html").c_str());
  return report_missing(s, w.missing, jobs.size());
}

}  // namespace

int run_study(const StudyArgs& a) {
  const auto t_start = std::chrono::steady_clock::now();
  if (a.jobs < 1) throw StudyError("--jobs must be >= 1");
  const std::string file = find_study(a.study);
  Study s = load_study(file, a.quick);
  apply_study_sets(s, a.sets);
  if (a.out.empty()) throw StudyError("--out DIR is required");
  const fs::path out(a.out);
  prepare_out_dir(a, out);

  // Scenes, configurations, jobs. Everything is validated before the first render.
  const std::vector<SceneData> scenes = load_scenes(s);
  const std::vector<Configuration> configs = expand(s);
  ReferenceCache refs((out / "references").string());
  const JobPlan plan = plan_jobs(s, file, scenes, configs, refs);
  const std::vector<Job>& jobs = plan.jobs;

  std::vector<std::string> columns = metric_columns(s);
  ResultStore store(a.shard.active() ? shard_dir(a.out, a.shard) : out.string(), s.name, columns);
  store.load();
  Work w;
  w.known = known_rows(a, s, columns, store);
  std::set<std::string> done;
  for (const Row& r : w.known) done.insert(r.id);
  if (a.plan) {
    fill_plan(*a.plan, jobs, done);
    return 0;
  }
  select_jobs(a, jobs, done, w);
  w.stale = stale_ids(w.known, jobs, scenes);
  if (!w.stale.empty() && !a.quiet)
    std::fprintf(stderr, "%zu stored row(s) were computed from older inputs (scene files, meshes, textures or the "
                 "renderer changed since): recomputing them\n", w.stale.size());

  // References first (sequential, each with every thread), then the jobs.
  const std::vector<const ReferenceJob*> ref_todo = references_to_render(w.pending, refs);
  if (!a.quiet)
    std::fprintf(stderr, "study %s%s%s: %zu scene(s) x %zu configuration(s) x %zu seed(s) = %zu job(s), %zu to run, %zu reference(s) to render, --jobs %d\n",
                 s.name.c_str(), a.quick ? " (quick)" : "",
                 a.shard.active() ? fmt::format(" shard {}/{}", a.shard.index, a.shard.count).c_str() : "", scenes.size(),
                 configs.size(), s.seeds.size(), jobs.size(), w.pending.size(), ref_todo.size(), a.jobs);

  render_all(a, s, scenes, refs, ref_todo, w.pending, store);
  if (g_interrupted) {
    std::fprintf(stderr, "interrupted: %zu row(s) saved in %s; run the same command again to resume\n", store.size(),
                 (out / "results.csv").c_str());
    return 130;
  }
  if (a.shard.active()) {  // the report is the merge's
    if (!a.quiet)
      std::fprintf(stderr, "shard %d/%d: %zu job(s) run, rows in %s; gather all shards with --merge\n", a.shard.index,
                   a.shard.count, w.pending.size(), (fs::path(shard_dir(a.out, a.shard)) / "results.csv").c_str());
    return 0;
  }
  return finish_study(a, s, plan, w, store, refs, t_start);
}

}  // namespace rl::study
