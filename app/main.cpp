// The `restir` command line: render, view, info, compare, options. Every error becomes one line
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
#include <nlohmann/json.hpp>

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
namespace fs = std::filesystem;

namespace {

// A mistake in how the command was called (exit status 2), as opposed to bad input (1).
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

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

struct RenderArgs {
  std::string scene, out, png, average, frame_dir, timings, config;
  std::string integrator, res, tonemap;
  int spp = 0, frames = 0, threads = -1;
  int64_t seed = -1;
  std::vector<std::string> sets;
  bool quiet = false;
};

std::string one_line(std::string s) {
  std::replace(s.begin(), s.end(), '\n', ' ');
  std::replace(s.begin(), s.end(), '\r', ' ');
  return s;
}

std::string replace_extension(const std::string& path, const char* ext) {
  fs::path p(path);
  p.replace_extension(ext);
  return p.string();
}

// Every output of the render, checked (and its folder created) before the render starts.
std::string check_render_outputs(const RenderArgs& a, const Scene& scene, const Options& o) {
  std::vector<OutputFile> outs;
  if (!a.out.empty()) outs.push_back({a.out, "-o", {".exr"}});
  if (!a.png.empty()) outs.push_back({a.png, "--png", {".png"}});
  if (!a.average.empty()) outs.push_back({a.average, "--average", {".exr"}});
  if (!a.timings.empty()) outs.push_back({a.timings, "--timings", {".csv"}});
  if (!a.frame_dir.empty()) outs.push_back({a.frame_dir, "--frame-dir", {}, true});
  const std::string main_out = !a.out.empty() ? a.out : (!a.png.empty() ? a.png : a.average);
  std::string sidecar = main_out.empty() ? "" : replace_extension(main_out, ".json");
  if (!sidecar.empty()) outs.push_back({sidecar, "the JSON sidecar of " + main_out, {".json"}, false, true});
  std::vector<std::string> inputs = scene.input_files;
  if (inputs.empty()) inputs.push_back(a.scene);
  if (!a.config.empty()) inputs.push_back(a.config);
  if (!o.render.camera_path.empty()) inputs.push_back(o.render.camera_path);
  // The frame files DIR/frame_NNNN.exr must not be an input or another output either (checked by
  // name: enumerating up to 100000 frame paths against every other path would be quadratic).
  if (!a.frame_dir.empty()) {
    std::vector<std::string> others = inputs;
    for (const OutputFile& f : outs)
      if (!f.directory) others.push_back(f.path);
    for (const std::string& p : others) {
      const fs::path pp(p);
      const std::string name = pp.filename().string();
      int f = -1;
      if (std::sscanf(name.c_str(), "frame_%d.exr", &f) == 1 && f >= 0 && f < o.render.frames &&
          name == fmt::format("frame_{:04d}.exr", f) &&
          same_file(pp.parent_path().empty() ? "." : pp.parent_path().string(), a.frame_dir))
        throw IoError(fmt::format("--frame-dir '{}': frame {} would overwrite '{}'", a.frame_dir, f, p));
    }
  }
  check_outputs(outs, inputs);
  return sidecar;
}

void write_outputs(const std::string& exr, const std::string& png, const Image& img, const Options& o,
                   const std::vector<std::pair<std::string, std::string>>& meta) {
  if (!exr.empty()) write_exr(exr, img, meta);
  if (!png.empty()) write_png(png, tonemap(img, o.output));
}

// --timings: one row per frame, its wall time and each stage's (stage_times.h); a stage a frame did
// not run (e.g. temporal reuse on frame 0) is 0.
std::string timings_csv(const RenderResult& r) {
  const std::vector<std::string> names = stage_names(r.frame_stages);
  std::string csv = "frame,ms";
  for (const auto& n : names) csv += "," + n + "_ms";
  csv += "\n";
  for (size_t i = 0; i < r.frame_ms.size(); ++i) {
    csv += fmt::format("{},{:.3f}", i, r.frame_ms[i]);
    for (const auto& n : names) csv += fmt::format(",{:.3f}", i < r.frame_stages.size() ? r.frame_stages[i].of(n) : 0.0);
    csv += "\n";
  }
  return csv;
}

int run_render(const RenderArgs& a) {
  if (a.out.empty() && a.png.empty() && a.average.empty() && a.frame_dir.empty())
    throw UsageError("render: no output: give -o OUT.exr and/or --png OUT.png");
  Scene scene = load_scene(a.scene);
  Options o;
  apply_scene_hints(o, scene.hints);
  if (!a.config.empty()) apply_options_file(o, a.config);
  // Dedicated flags are shorthands for --set; they are applied after the config file.
  if (!a.integrator.empty()) set_option(o, "integrator", a.integrator);
  if (a.spp > 0) set_option(o, "render.spp", std::to_string(a.spp));
  if (a.frames > 0) set_option(o, "render.frames", std::to_string(a.frames));
  if (a.threads >= 0) set_option(o, "render.threads", std::to_string(a.threads));
  if (a.seed >= 0) set_option(o, "render.seed", std::to_string(a.seed));
  if (!a.tonemap.empty()) set_option(o, "output.tonemap", a.tonemap);
  if (!a.res.empty()) {
    auto x = a.res.find('x');
    if (x == std::string::npos) throw OptionError("--res: expected WxH, got '" + a.res + "'");
    set_option(o, "film.width", a.res.substr(0, x));
    set_option(o, "film.height", a.res.substr(x + 1));
  }
  for (const auto& s : a.sets) set_option_assignment(o, s);
  validate_options(o);
  find_integrator(o.integrator);  // fail before any output if the name is unknown
  const std::string sidecar = check_render_outputs(a, scene, o);

  const std::string config_json = options_to_json(o, -1);
  std::vector<std::pair<std::string, std::string>> meta = {
      {"restir.version", rl::build_id()}, {"restir.scene", a.scene}, {"restir.config", config_json}};
  if (!a.quiet) {
    std::fprintf(stderr, "restir %s: %s, integrator %s, %dx%d, %d spp, %d frame(s)\n", rl::build_id(), a.scene.c_str(),
                 o.integrator.c_str(), o.film.width, o.film.height, o.render.spp, o.render.frames);
  }
  RenderHooks hooks;
  hooks.progress_bar = !a.quiet;
  hooks.on_frame = [&](int f, const Image& img, double ms) {
    if (!a.quiet && o.render.frames > 1) std::fprintf(stderr, "\r\033[Kframe %d: %.1f ms\n", f, ms);
    if (!a.frame_dir.empty()) {
      auto m = meta;
      m.emplace_back("restir.frame", std::to_string(f));
      write_exr(fmt::format("{}/frame_{:04d}.exr", a.frame_dir, f), img, m);
    }
  };
  RenderResult r = render(scene, o, hooks);

  write_outputs(a.out, a.png, r.last, o, meta);
  if (!a.average.empty()) write_exr(a.average, r.average, meta);
  if (!a.timings.empty()) write_text_file_atomic(a.timings, timings_csv(r));
  // JSON sidecar beside the main output: configuration, scene, version and timings. The marker
  // key lets a later run tell its own sidecar from a user's JSON file of the same name.
  if (!sidecar.empty()) {
    nlohmann::ordered_json side;
    side[kSidecarMarker] = 1;
    side["version"] = rl::build_id();
    side["scene"] = a.scene;
    side["config"] = nlohmann::ordered_json::parse(config_json);
    side["frame_ms"] = r.frame_ms;
    nlohmann::ordered_json stages = nlohmann::ordered_json::array();
    for (const StageTimes& st : r.frame_stages) {
      nlohmann::ordered_json one = nlohmann::ordered_json::object();
      for (const auto& [name, ms] : st.ms) one[name] = ms;
      stages.push_back(std::move(one));
    }
    side["stage_ms"] = std::move(stages);
    write_text_file_atomic(sidecar, side.dump(2) + "\n");
  }
  if (!a.quiet) {
    double total = 0;
    for (double ms : r.frame_ms) total += ms;
    std::fprintf(stderr, "rendered %d frame(s) in %.1f ms (%.1f ms/frame)\n", o.render.frames, total,
                 total / double(r.frame_ms.size()));
  }
  return 0;
}

struct ExportArgs {
  std::string scene, out, config;
  std::vector<std::string> sets;
};

// The options a `render` of the same scene would use (scene hints < --config < --set), so that
// resolution, spp, filter and max depth in the export are the effective ones.
int run_export_mitsuba(const ExportArgs& a) {
  Scene scene = load_scene(a.scene);
  Options o;
  apply_scene_hints(o, scene.hints);
  if (!a.config.empty()) apply_options_file(o, a.config);
  for (const auto& s : a.sets) set_option_assignment(o, s);
  validate_options(o);
  Camera camera = scene.camera;
  if (!o.render.camera_path.empty()) load_camera_path(o.render.camera_path, camera);
  if (camera.keys.empty()) camera.keys.push_back(CameraKey{});
  MitsubaExportSettings s;
  s.width = o.film.width;
  s.height = o.film.height;
  s.spp = o.render.spp;
  s.max_depth = o.path.max_depth;
  s.filter = format_value(o.film.filter);
  s.filter_radius = o.film.filter_radius;
  s.camera = camera.at_frame(o.render.frames - 1, o.render.frames);  // the frame `render -o` writes
  for (const std::string& n : export_mitsuba(scene, s, a.out)) std::fprintf(stderr, "note: %s\n", n.c_str());
  fmt::print("{}/scene.xml: {}x{}, {} spp, Mitsuba max_depth {} (path.max_depth {})\n", a.out, s.width, s.height,
             s.spp, s.max_depth + 1, s.max_depth);
  return 0;
}

int run_info(const std::string& path) {
  Scene scene = load_scene(path);
  Lights lights(scene, LightSelection::power);
  Bounds3 b = scene.bounds();
  size_t emissive_meshes = 0;
  for (const auto& m : scene.meshes) emissive_meshes += m.emission ? 1 : 0;
  fmt::print("scene       {}\n", path);
  fmt::print("meshes      {} ({} triangles, {} emissive meshes)\n", scene.meshes.size(), scene.triangle_count(), emissive_meshes);
  fmt::print("spheres     {}\n", scene.spheres.size());
  fmt::print("materials   {}\n", scene.materials.size());
  fmt::print("textures    {}\n", scene.textures.size());
  fmt::print("emitters    {} (point lights {}, environment {})\n", lights.emitter_count(), scene.point_lights.size(),
             scene.environment ? (scene.environment->filename.empty() ? "constant" : scene.environment->filename) : "none");
  fmt::print("bounds      ({:.4g}, {:.4g}, {:.4g}) - ({:.4g}, {:.4g}, {:.4g})\n", b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z);
  if (!scene.camera.keys.empty()) {
    PerspectiveCamera cam(scene.camera.keys.front(), 16, 16);
    Vec3 p = cam.position(), d = cam.forward();
    fmt::print("camera      at ({:.4g}, {:.4g}, {:.4g}) looking ({:.3f}, {:.3f}, {:.3f}), fov {:.4g}, {} key(s)\n", p.x, p.y,
               p.z, d.x, d.y, d.z, scene.camera.keys.front().fov_degrees, scene.camera.keys.size());
  }
  const SceneHints& h = scene.hints;
  fmt::print("film        {}x{}, spp {}, max depth {}\n", h.width ? std::to_string(*h.width) : "-",
             h.height ? std::to_string(*h.height) : "-", h.spp ? std::to_string(*h.spp) : "-",
             h.max_depth ? std::to_string(*h.max_depth) : "-");
  return 0;
}

// Display-referred (tone-mapped, sRGB 8-bit) files against scene-linear ones give meaningless metrics.
bool display_referred(const std::string& path) {
  std::string e = fs::path(path).extension().string();
  for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
  return e == ".png" || e == ".jpg" || e == ".jpeg" || e == ".bmp" || e == ".tga";
}

int run_compare(const std::string& a, const std::string& b, bool json) {
  if (display_referred(a) != display_referred(b))
    throw OptionError(fmt::format("compare: '{}' is {} but '{}' is {}: the metrics would be meaningless; compare "
                                  "two linear images (EXR) or two tone-mapped ones", a,
                                  display_referred(a) ? "tone-mapped (8-bit sRGB)" : "linear HDR", b,
                                  display_referred(b) ? "tone-mapped (8-bit sRGB)" : "linear HDR"));
  Image test = read_image(a), ref = read_image(b);
  double m = mse(test, ref), r = rel_mse(test, ref), e = mean_abs_error(test, ref);
  double lt = image_stats(test).mean_luminance, lr = image_stats(ref).mean_luminance;
  if (json) {
    fmt::print("{{\"mse\": {:.9g}, \"relmse\": {:.9g}, \"mae\": {:.9g}, \"mean_luminance_test\": {:.9g}, "
               "\"mean_luminance_reference\": {:.9g}}}\n", m, r, e, lt, lr);
  } else {
    fmt::print("MSE     {:.6g}\nrelMSE  {:.6g}\nMAE     {:.6g}\nmean luminance  test {:.6g}  reference {:.6g}\n", m, r, e,
               lt, lr);
  }
  return 0;
}

// Every subcommand, and where CLI11 stores its arguments (it binds them by reference: a Commands
// must stay where it is from the first add_* to the last run).
struct Commands {
  RenderArgs ra;
  std::string info_scene;
  std::string cmp_a, cmp_b;
  bool cmp_json = false;
  ExportArgs ea;
  viewer::ViewArgs va;
  study::StudyArgs sa;
  bool study_list = false;
  std::string shard_text;
  bool slurm = false;
  study::SlurmArgs sl;
  CLI::App *render = nullptr, *info = nullptr, *compare = nullptr, *export_mi = nullptr, *view = nullptr,
           *options = nullptr, *study_cmd = nullptr;
};

void add_render_command(CLI::App& app, Commands& c) {
  RenderArgs& ra = c.ra;
  auto* render = c.render = app.add_subcommand("render", "render a scene to EXR/PNG");
  render->add_option("scene", ra.scene, "scene file (.pbrt, .obj, .gltf, .glb, .ply)")->required();
  render->add_option("-o,--output", ra.out, "HDR output of the last frame (.exr)");
  render->add_option("--png", ra.png, "tone-mapped PNG of the last frame");
  render->add_option("--average", ra.average, "EXR of the mean over all frames");
  render->add_option("--frame-dir", ra.frame_dir, "write every frame as DIR/frame_NNNN.exr");
  render->add_option("--timings", ra.timings, "CSV of per-frame wall time");
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
  compare->add_option("test", c.cmp_a, "test image")->required();
  compare->add_option("reference", c.cmp_b, "reference image")->required();
  compare->add_flag("--json", c.cmp_json, "print JSON");
}

void add_export_command(CLI::App& app, Commands& c) {
  ExportArgs& ea = c.ea;
  auto* export_mi = c.export_mi = app.add_subcommand("export-mitsuba", "write the parsed scene as a Mitsuba 3 scene (DIR/scene.xml + PLY/EXR)");
  export_mi->add_option("scene", ea.scene, "scene file")->required();
  export_mi->add_option("--out", ea.out, "output folder")->required();
  export_mi->add_option("--set", ea.sets, "set an option as for render: key=value (film.width, path.max_depth, ...)");
  export_mi->add_option("--config", ea.config, "JSON file of options (applied before --set)");
  export_mi->footer("Mitsuba's max_depth is path.max_depth + 1 (it counts the camera segment). See src/scene/mitsuba_export.h.");
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
  view->add_option("--script", va.script, "run a script of commands (set, frames, screenshot, ...; see src/viewer/script.h) and exit");
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
  study_cmd->add_flag("--dry-run", sl.dry_run, "--slurm: print the job scripts and sbatch commands; submit nothing");
  study_cmd->footer("Resumable: rows already in OUT/results.json (or OUT/shards/*) are not recomputed. Format: studies/README.md.\n"
                    "Cluster: --slurm submits, --shard/--merge are what its tasks run; see README \"Running on a cluster\".");
}

// Usage errors: one line, exit status 2 (not CLI11's 104-114), a pointer to --help.
int usage_error(const CLI::ParseError& e, int argc, char** argv) {
  std::string msg = e.what();
  const char* commands = "render, view, info, compare, study, options";
  if (argc <= 1) msg = fmt::format("a command is required ({})", commands);
  else if (argv[1][0] != '-' &&
           std::string(" render view info compare study options ").find(" " + std::string(argv[1]) + " ") == std::string::npos)
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
                          study_cmd->count("--time") || study_cmd->count("--cpus");
  if (c.slurm && (sa.merge || sa.shard.active())) throw UsageError("study: --slurm submits shards and merge itself; drop --shard/--merge");
  if (!c.slurm && slurm_only) throw UsageError("study: --shards, --partition, --time, --cpus and --dry-run belong to --slurm");
  if (c.slurm) return study::submit_study_slurm(sa, sl);
  return study::run_study(sa);
}

int run_options() {
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
  if (*c.compare) return run_compare(c.cmp_a, c.cmp_b, c.cmp_json);
  if (*c.view) {
#ifdef RESTIR_HAVE_VIEWER
    return viewer::run_view(c.va);
#else
    throw OptionError("view: this build has no viewer (configure with -DRESTIR_VIEWER=ON; it needs the Debian "
                      "packages libglfw3-dev, libimgui-dev and libgl-dev)");
#endif
  }
  if (*c.study_cmd) return run_study_command(c);
  if (*c.options) return run_options();
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
