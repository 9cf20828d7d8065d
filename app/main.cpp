// The `restir` command line: render, view, info, compare, tonemap, study, options, export-mitsuba. Every error becomes one line
// "error: ..." on stderr and one exit status: 0 ok, 1 bad input or runtime error, 2 usage (bad
// flags, missing arguments), 130 interrupted.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <climits>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "backends/cuda/cuda_queries.h"
#include "core/build_info.h"
#include "core/io_error.h"
#include "core/option_io.h"
#include "core/output_guard.h"
#include "image/image_io.h"
#include "image/metrics.h"
#include "image/tonemap.h"
#include "frame/integrator.h"
#include "frame/render.h"
#include "scene/lights.h"
#include "scene/camera.h"
#include "scene/loader.h"
#include "scene/mitsuba_export.h"
#include "study/runner.h"
#include "study/slurm.h"
#include "study/study_file.h"
#include "viewer/session.h"
#ifdef RESTIR_HAVE_VIEWER
#include "viewer/view.h"
#endif

using namespace rl;

using namespace rl::cli;

namespace {

// Every subcommand, and where CLI11 stores its arguments (it binds them by reference: a Commands
// must stay where it is from the first add_* to the last run).
struct Commands {
  RenderArgs ra;
  std::string info_scene;
  CompareArgs cmp;
  TonemapArgs tm;
  std::string options_prefix;
  ExportArgs ea;
  viewer::ViewArgs va;
  study::StudyArgs sa;
  bool study_list = false;
  std::string shard_text;
  bool slurm = false;
  study::SlurmArgs sl;
  CLI::App *render = nullptr, *info = nullptr, *compare = nullptr, *export_mi = nullptr, *view = nullptr,
           *options = nullptr, *study_cmd = nullptr, *tonemap = nullptr;
};

void add_render_command(CLI::App& app, Commands& c) {
  RenderArgs& ra = c.ra;
  auto* render = c.render = app.add_subcommand("render", "render a scene to EXR/PNG");
  render->add_option("scene", ra.scene, "scene file (.pbrt, .obj, .gltf, .glb, .ply)")->required();
  render->add_option("-o,--output", ra.out, "HDR output of the last frame (.exr)");
  render->add_option("--png", ra.png, "tone-mapped PNG of the last frame");
  render->add_option("--average", ra.average, "EXR of the mean over all frames");
  render->add_option("--frame-dir", ra.frame_dir, "write every frame as DIR/frame_NNNN.exr (and/or .png: --frame-format)");
  render->add_option("--frame-format", ra.frame_format, "--frame-dir's files: exr (linear), png (tone-mapped), or both")
      ->check(CLI::IsMember({"exr", "png", "both"}));
  render->add_option("--aov-dir", ra.aov_dir, "write every frame's AOVs (albedo, normal, depth, motion, emission, surface id) as DIR/aov_NNNN.exr (docs/denoise.md)");
  render->add_option("--timings", ra.timings, "CSV of each frame's wall time and each stage's (primary, candidates, temporal, spatial, shading, ...)");
  render->add_flag("--stats", ra.stats, "print each stage's median ms per frame and share of the frame time after the render");
  render->add_option("--integrator", ra.integrator, "integrator name (= --set integrator=NAME)");
  render->add_option("--spp", ra.spp, "samples per pixel (= --set render.spp=N)")->check(integer_in(1, INT_MAX));
  render->add_option("--res", ra.res, "resolution WxH (= film.width / film.height)");
  render->add_option("--seed", ra.seed, "random seed (= render.seed)")->check(integer_in(0, INT64_MAX));
  render->add_option("--frames", ra.frames, "frames in the sequence (= render.frames)")->check(integer_in(1, INT_MAX));
  render->add_option("--threads", ra.threads, "worker threads, 0 = all (= render.threads)")->check(integer_in(0, INT_MAX));
  render->add_option("--tonemap", ra.tonemap, "PNG tone mapper (= output.tonemap)");
  render->add_option("--set", ra.sets, "set any option: key=value (repeatable; see `restir options`)");
  render->add_option("--config", ra.config, "JSON file of options (applied before --set)");
  render->add_flag("-q,--quiet", ra.quiet, "no progress or summary on stderr");
  render->footer("Option precedence: defaults < scene file < --config < flags < --set. `restir options` lists every key.");
}

void add_info_and_compare_commands(CLI::App& app, Commands& c) {
  c.info = app.add_subcommand("info", "print scene statistics");
  c.info->add_option("scene", c.info_scene, "scene file")->required();

  auto* compare = c.compare = app.add_subcommand("compare", "error metrics of TEST against REFERENCE (MSE, relMSE, MAE)");
  compare->add_option("test", c.cmp.test, "test image")->required();
  compare->add_option("reference", c.cmp.reference, "reference image")->required();
  compare->add_option("--error-map", c.cmp.error_map, "write the per-pixel FLIP error as a false-colour PNG with its scale bar");
  compare->add_option("--crop", c.cmp.crop, "compare only the region X,Y,W,H (pixels; x right, y down from the top-left corner)");
  compare->add_flag("--json", c.cmp.json, "print JSON");
  compare->footer("relMSE is pbrt's (eps 0.01); FLIP is LDR-FLIP (Andersson et al. 2020) of the images tone-mapped as the test image\n"
                  "was rendered (its EXR header), as a study computes it. Warns when the images' recorded configurations\n"
                  "estimate different integrals (e.g. restir-di's direct light against a path-traced reference).");
  auto* tonemap = c.tonemap = app.add_subcommand("tonemap", "write an EXR as a tone-mapped PNG (the tone mapping it was rendered with, or --set output.*)");
  tonemap->add_option("input", c.tm.in, "linear image (.exr, .hdr)")->required();
  tonemap->add_option("output", c.tm.out, "PNG to write")->required();
  tonemap->add_option("--set", c.tm.sets, "output.tonemap, output.exposure, output.white_point, output.srgb (key=value)");
}

void add_export_command(CLI::App& app, Commands& c) {
  ExportArgs& ea = c.ea;
  auto* export_mi = c.export_mi = app.add_subcommand("export-mitsuba", "write the parsed scene as a Mitsuba 3 scene (DIR/scene.xml + PLY/EXR)");
  export_mi->add_option("scene", ea.scene, "scene file")->required();
  export_mi->add_option("--out", ea.out, "output folder")->required();
  export_mi->add_option("--set", ea.sets, "set an option as for render: key=value (film.width, path.max_depth, ...)");
  export_mi->add_option("--config", ea.config, "JSON file of options (applied before --set)");
  export_mi->footer("Mitsuba's max_depth is path.max_depth + 1 (it counts the camera segment). README \"Validation against Mitsuba 3\" says what is exported.");
}

void add_view_command(CLI::App& app, Commands& c) {
  viewer::ViewArgs& va = c.va;
  auto* view = c.view = app.add_subcommand("view", "interactive viewer: the frame re-rendered live, every option editable");
  view->add_option("scene", va.scene, "scene file (.pbrt, .obj, .gltf, .glb, .ply)")->required();
  view->add_option("--integrator", va.integrator, "integrator name (= --set integrator=NAME)");
  view->add_option("--spp", va.spp, "samples per pixel per frame (default 1: the viewer accumulates frames)")->check(integer_in(1, INT_MAX));
  view->add_option("--set", va.sets, "set any option: key=value (repeatable; see `restir options`)");
  view->add_option("--config", va.config, "JSON file of options (applied before --set)");
  view->add_option("--reference", va.reference, "converged EXR of the same view: relMSE / FLIP readouts, error map, A/B split");
  view->add_flag("--background-reference", va.background_reference,
                 "render a pt reference of the view beside the frames (it restarts when the view changes): relMSE / FLIP, error map, A/B split without --reference");
  view->add_option("--redraw-budget", va.redraw_budget,
                   "share of wall time the window may spend redrawing while nothing moves (default 0.03; 1: redraw every frame)")
      ->check(CLI::Range(0.001f, 1.0f));
  view->add_option("--scale", va.scale, "render scale: 1, 0.5 or 0.25 of film.width x film.height")->check(CLI::IsMember({1.0f, 0.5f, 0.25f}));
  view->add_option("--script", va.script, "run a script of commands and exit: one a line, set KEY VALUE | frames N | screenshot PATH | view radiance|error|split | "
                 "split F | accumulate on|off | scale S | camera orbit|move|reset|mode ... | record start|stop|save PATH | "
                 "reference on [SPP]|off|wait | save-config PATH | quit ('#' comments; README \"Interactive viewer\")");
  view->add_option("--bench", va.bench, "render N frames bare and N through the viewer loop; print ms/frame and the ratio")->check(integer_in(1, 100000));
  view->footer("Controls: left drag turns (orbit / fly), right drag pans, wheel dollies, WASD + Q/E move, R resets the camera,\n"
               "Space pauses. Option precedence: defaults < scene file < render.spp=1 < --config < flags < --set.");
}

void add_study_command(CLI::App& app, Commands& c) {
  study::StudyArgs& sa = c.sa;
  study::SlurmArgs& sl = c.sl;
  auto* study_cmd = c.study_cmd = app.add_subcommand("study", "run a parameter study: sweep, metrics, CSV, plots, report.html");
  study_cmd->add_option("study", sa.study, "built-in study name (see --list) or path to a study JSON file");
  study_cmd->add_option("--out", sa.out, "output folder (results, references, images, plots, report.html)");
  study_cmd->add_flag("--quick", sa.quick, "apply the study's \"quick\" block (tiny resolution, few seeds and frames)");
  study_cmd->add_option("--set", sa.sets, "KEY=VALUE over the study's base for every configuration, repeatable (e.g. render.backend=cuda: "
                                          "the study and its references on the GPU); an axis of the same key still sweeps it")
      ->allow_extra_args(false);
  study_cmd->add_option("--jobs", sa.jobs, "configurations rendered in parallel (they share the cores)")->check(integer_in(1, INT_MAX));
  study_cmd->add_flag("--list", c.study_list, "list the built-in studies");
  study_cmd->add_flag("-q,--quiet", sa.quiet, "no progress or summary on stderr");
  study_cmd->add_option("--shard", c.shard_text, "I/N: run only shard I of N (0-based) of the jobs, rows into OUT/shards/I-of-N");
  study_cmd->add_flag("--merge", sa.merge, "run nothing: gather OUT and every OUT/shards/* into results, plots and report; exit 1 if jobs are missing");
  study_cmd->add_flag("--slurm", c.slurm, "submit the study as a Slurm job array of --shards tasks plus a dependent merge job");
  study_cmd->add_option("--shards", sl.shards, "--slurm: array tasks (default 4)")->check(integer_in(1, 100000));
  study_cmd->add_option("--partition", sl.partition, "--slurm: sbatch --partition");
  study_cmd->add_option("--time", sl.time, "--slurm: sbatch --time limit per task (e.g. 2:00:00)");
  study_cmd->add_option("--cpus", sl.cpus, "--slurm: sbatch --cpus-per-task")->check(integer_in(1, 4096));
  study_cmd->add_option("--sbatch-arg", sl.sbatch_args, "--slurm: any other sbatch option, repeatable (--sbatch-arg=--account=NAME --sbatch-arg=--mem=8G)")
      ->allow_extra_args(false);
  study_cmd->add_flag("--dry-run", sl.dry_run, "--slurm: print the job scripts and sbatch commands; submit nothing");
  study_cmd->footer("Resumable: rows already in OUT/results.json (or OUT/shards/*) are not recomputed. Format: studies/README.md.\n"
                    "Cluster: --slurm submits, --shard/--merge are what its tasks run; see README \"Running on a cluster\".");
}

// Usage errors: one line, exit status 2 (not CLI11's 104-114), a pointer to --help.
int usage_error(const CLI::ParseError& e, int argc, char** argv) {
  std::string msg = e.what();
  const char* commands = "render, view, info, compare, tonemap, study, options, export-mitsuba";
  if (argc <= 1) msg = fmt::format("a command is required ({})", commands);
  else if (argv[1][0] != '-' &&
           std::string(" render view info compare tonemap study options export-mitsuba ").find(" " + std::string(argv[1]) + " ") == std::string::npos)
    msg = fmt::format("unknown command '{}' (commands: {})", argv[1], commands);
  std::replace(msg.begin(), msg.end(), '\n', ' ');
  std::fprintf(stderr, "error: %s; see `restir --help`\n", msg.c_str());
  return 2;
}

int run_study_command(Commands& c) {
  study::StudyArgs& sa = c.sa;
  const study::SlurmArgs& sl = c.sl;
  const CLI::App* study_cmd = c.study_cmd;
  if (c.study_list) {
    for (const auto& [name, description] : study::list_studies()) fmt::print("{:<18} {}\n", name, description);
    return 0;
  }
  if (sa.study.empty()) throw UsageError("study: give a study name or file (or --list)");
  if (sa.out.empty()) throw UsageError("study: --out DIR is required");
  if (!c.shard_text.empty()) sa.shard = study::parse_shard(c.shard_text);
  const bool slurm_only = sl.dry_run || study_cmd->count("--shards") || study_cmd->count("--partition") ||
                          study_cmd->count("--time") || study_cmd->count("--cpus") || study_cmd->count("--sbatch-arg");
  if (c.slurm && (sa.merge || sa.shard.active())) throw UsageError("study: --slurm submits shards and merge itself; drop --shard/--merge");
  if (!c.slurm && slurm_only) throw UsageError("study: --shards, --partition, --time, --cpus, --sbatch-arg and --dry-run belong to --slurm");
  if (c.slurm) return study::submit_study_slurm(sa, sl);
  return study::run_study(sa);
}

// `restir options [PREFIX]`: the integrators and every option, or the options whose key starts
// with PREFIX ("pt.", "render.spp").
int run_options(const std::string& prefix) {
  if (!prefix.empty()) {
    fmt::print("{}", options_help(prefix));
    return 0;
  }
  std::string integrators;
  for (const auto& i : integrator_registry()) integrators += fmt::format("  {:<12} {}\n", i.name, i.description);
  fmt::print("Integrators:\n{}\n{}", integrators, options_help());
  return 0;
}

// Runs the command that was parsed; throws on errors (UsageError for how it was called).
int run_command(Commands& c) {
  if (*c.render) return run_render(c.ra);
  if (*c.info) return run_info(c.info_scene);
  if (*c.export_mi) return run_export_mitsuba(c.ea);
  if (*c.compare) return run_compare(c.cmp);
  if (*c.tonemap) return run_tonemap(c.tm);
  if (*c.view) {
#ifdef RESTIR_HAVE_VIEWER
    return viewer::run_view(c.va);
#else
    throw OptionError("view: this build has no viewer (configure with -DRESTIR_VIEWER=ON; it needs the Debian "
                      "packages libglfw3-dev, libimgui-dev and libgl-dev)");
#endif
  }
  if (*c.study_cmd) return run_study_command(c);
  if (*c.options) return run_options(c.options_prefix);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"restir-lab: a research renderer and parameter-study lab for ReSTIR (CPU, and NVIDIA GPUs with CUDA)"};
  app.require_subcommand(1);
  // The build id, then whether render.backend=cuda can run here (and why not).
  app.set_version_flag("--version", [] {
    const std::string why = rl::cuda_unavailable_reason();
    return std::string(rl::build_id()) + "\ncuda backend: " +
           (why.empty() ? "ready (" + rl::cuda_device_description() + ")" : "unavailable: " + why);
  });
  Commands c;
  add_render_command(app, c);
  add_info_and_compare_commands(app, c);
  add_export_command(app, c);
  add_view_command(app, c);
  c.options = app.add_subcommand("options", "list every option key with its type, default and meaning");
  c.options->add_option("prefix", c.options_prefix, "only the keys that start with PREFIX (e.g. pt. or render.spp)");
  add_study_command(app, c);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return usage_error(e, argc, argv);
  }
  try {
    return run_command(c);
  } catch (const UsageError& e) {
    std::fprintf(stderr, "error: %s; see `restir --help`\n", one_line(e.what()).c_str());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", one_line(e.what()).c_str());
    return 1;
  }
}

namespace rl::cli {

// CLI11's own range validators print DBL_MAX in full and say "0 not in range 0.000000 to ...".
CLI::Validator integer_in(int64_t lo, int64_t hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        int64_t v = 0;
        auto r = std::from_chars(text.data(), text.data() + text.size(), v);
        if (r.ec != std::errc() || r.ptr != text.data() + text.size() || v < lo || v > hi)
          return fmt::format("expected an integer in [{}, {}], got '{}'", lo, hi, text);
        return {};
      },
      fmt::format("INT in [{}, {}]", lo, hi));
}

std::string one_line(std::string s) {
  std::replace(s.begin(), s.end(), '\n', ' ');
  std::replace(s.begin(), s.end(), '\r', ' ');
  return s;
}

}  // namespace rl::cli
