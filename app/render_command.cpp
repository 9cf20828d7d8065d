// `restir render`, `export-mitsuba` and `info`: a scene in, images (or a scene, or a summary) out.
#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include "cli.h"
#include "core/build_info.h"
#include "core/io_error.h"
#include "core/option_io.h"
#include "core/output_guard.h"
#include "frame/integrator.h"
#include "frame/render.h"
#include "image/image_io.h"
#include "image/tonemap.h"
#include "scene/camera.h"
#include "scene/lights.h"
#include "scene/loader.h"
#include "scene/mitsuba_export.h"

namespace rl::cli {

namespace fs = std::filesystem;

namespace {

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
  if (!a.aov_dir.empty()) outs.push_back({a.aov_dir, "--aov-dir", {}, true});
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
      for (const char* ext : {"exr", "png"})
        if (std::sscanf(name.c_str(), "frame_%d.", &f) == 1 && f >= 0 && f < o.render.frames &&
            name == fmt::format("frame_{:04d}.{}", f, ext) && (a.frame_format == "both" || a.frame_format == ext) &&
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
// not run (e.g. temporal reuse on frame 0) is 0. Then the rays per pixel each stage traced, by kind
// (closest hit, any hit), and the frame's totals (core/ray_counter.h: every integrator counts).
std::string timings_csv(const RenderResult& r, size_t pixels) {
  const std::vector<std::string> names = stage_names(r.frame_stages), ray_names = ray_stage_names(r.frame_stages);
  std::string csv = "frame,ms";
  for (const auto& n : names) csv += "," + n + "_ms";
  for (const auto& n : ray_names) csv += "," + n + "_closest_px," + n + "_any_px";
  if (!ray_names.empty()) csv += ",closest_px,any_px";
  csv += "\n";
  const double px = double(std::max<size_t>(pixels, 1));
  for (size_t i = 0; i < r.frame_ms.size(); ++i) {
    const StageTimes none, &st = i < r.frame_stages.size() ? r.frame_stages[i] : none;
    csv += fmt::format("{},{:.3f}", i, r.frame_ms[i]);
    for (const auto& n : names) csv += fmt::format(",{:.3f}", st.of(n));
    for (const auto& n : ray_names) csv += fmt::format(",{:.4f},{:.4f}", double(st.rays_of(n).closest) / px, double(st.rays_of(n).any) / px);
    if (!ray_names.empty()) csv += fmt::format(",{:.4f},{:.4f}", double(st.total_rays().closest) / px, double(st.total_rays().any) / px);
    csv += "\n";
  }
  return csv;
}

}  // namespace

// --stats: each stage's median over the frames that ran it, its share of the median frame and,
// where it traced rays, its median rays per pixel by kind.
std::string stage_summary(const RenderResult& r, size_t pixels) {
  auto median = [](std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  const double frame = median(r.frame_ms), px = double(std::max<size_t>(pixels, 1));
  const bool rays = !ray_stage_names(r.frame_stages).empty();
  std::string s = fmt::format("{:<16} {:>10} {:>7}{}  (median over {} frame(s))\n", "stage", "ms/frame", "share",
                              rays ? fmt::format(" {:>10} {:>10}", "closest/px", "any/px") : "", r.frame_ms.size());
  // The median over the frames that ran the stage of value(frame's stages).
  const auto stage_median = [&](const std::string& n, const auto& value) {
    std::vector<double> v;
    for (const StageTimes& st : r.frame_stages)
      if (st.of(n) > 0) v.push_back(value(st));
    return std::pair{median(v), v.size()};
  };
  for (const std::string& n : stage_names(r.frame_stages)) {
    const auto [m, ran] = stage_median(n, [&](const StageTimes& st) { return st.of(n); });
    std::string ray_cols;
    if (rays) {
      const double c = stage_median(n, [&](const StageTimes& st) { return double(st.rays_of(n).closest); }).first / px;
      const double y = stage_median(n, [&](const StageTimes& st) { return double(st.rays_of(n).any); }).first / px;
      ray_cols = c + y > 0 ? fmt::format(" {:>10.3f} {:>10.3f}", c, y) : fmt::format(" {:>10} {:>10}", "", "");
    }
    s += fmt::format("{:<16} {:>10.3f} {:>6.1f}%{}{}\n", n, m, frame > 0 ? 100 * m / frame : 0.0, ray_cols,
                     ran < r.frame_ms.size() ? fmt::format("  (ran in {} of {} frames)", ran, r.frame_ms.size()) : "");
  }
  std::string total_cols;
  if (rays) {
    std::vector<double> c, y;
    for (const StageTimes& st : r.frame_stages) c.push_back(double(st.total_rays().closest)), y.push_back(double(st.total_rays().any));
    total_cols = fmt::format(" {:>10.3f} {:>10.3f}", median(c) / px, median(y) / px);
  }
  s += fmt::format("{:<16} {:>10.3f} {:>6.1f}%{}\n", "frame", frame, 100.0, total_cols);
  if (r.buffer_bytes > 0) s += fmt::format("buffers: {:.0f} bytes per pixel\n", double(r.buffer_bytes) / px);
  return s;
}

// The JSON sidecar of a render: configuration, scene, version, timings (frames and stages) and the
// rays each stage traced (counts; "pixels" turns them into rays per pixel).
static void write_sidecar(const std::string& path, const std::string& scene, const std::string& config_json, const RenderResult& r,
                          size_t pixels) {
  nlohmann::ordered_json side;
  side[kSidecarMarker] = 1;
  side["version"] = rl::build_id();
  side["scene"] = scene;
  side["config"] = nlohmann::ordered_json::parse(config_json);
  side["frame_ms"] = r.frame_ms;
  nlohmann::ordered_json stages = nlohmann::ordered_json::array(), rays = nlohmann::ordered_json::array();
  for (const StageTimes& st : r.frame_stages) {
    nlohmann::ordered_json one = nlohmann::ordered_json::object(), counted = nlohmann::ordered_json::object();
    for (const auto& [name, ms] : st.ms) one[name] = ms;
    for (const auto& [name, c] : st.rays) counted[name] = {{"closest", c.closest}, {"any", c.any}, {"queued", c.queued}};
    stages.push_back(std::move(one));
    rays.push_back(std::move(counted));
  }
  side["stage_ms"] = std::move(stages);
  side["pixels"] = pixels;
  side["stage_rays"] = std::move(rays);
  side["buffer_bytes"] = r.buffer_bytes;  // the integrator's buffers after the last frame
  write_text_file_atomic(path, side.dump(2) + "\n");
}

int run_render(const RenderArgs& a) {
  if (a.out.empty() && a.png.empty() && a.average.empty() && a.frame_dir.empty() && a.aov_dir.empty())
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
  for (const std::string& n : fit_defaults_to_integrator(o, /*sequence=*/true))
    if (!a.quiet || n.starts_with("warning: ")) std::fprintf(stderr, "%s%s\n", n.starts_with("warning: ") ? "" : "note: ", n.c_str());
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
  const bool stderr_tty = isatty(STDERR_FILENO);
  // With a denoiser, the frames written are the denoised ones (--average stays the raw mean).
  const bool denoised = o.denoise.method != DenoiseMethod::none;
  auto write_frame = [&](int f, const Image& img) {
    if (!a.frame_dir.empty() && a.frame_format != "png") {
      auto m = meta;
      m.emplace_back("restir.frame", std::to_string(f));
      write_exr(fmt::format("{}/frame_{:04d}.exr", a.frame_dir, f), img, m);
    }
    // PNG frames, tone-mapped as --png is: what a video encoder takes (ffmpeg -i DIR/frame_%04d.png).
    if (!a.frame_dir.empty() && a.frame_format != "exr") write_png(fmt::format("{}/frame_{:04d}.png", a.frame_dir, f), tonemap(img, o.output));
  };
  hooks.on_frame = [&](int f, const Image& img, double ms) {
    // "\r\033[K" clears the progress bar, which only a terminal shows (render.cpp): not in a log.
    if (!a.quiet && o.render.frames > 1) std::fprintf(stderr, "%sframe %d: %.1f ms\n", stderr_tty ? "\r\033[K" : "", f, ms);
    if (!denoised) write_frame(f, img);
  };
  if (denoised) hooks.on_denoised = write_frame;
  if (!a.aov_dir.empty())
    hooks.on_aovs = [&](int f, const Aovs& aovs) {
      auto m = meta;
      m.emplace_back("restir.frame", std::to_string(f));
      write_exr_channels(fmt::format("{}/aov_{:04d}.exr", a.aov_dir, f), aovs.width, aovs.height, aov_channels(aovs), m);
    };
  RenderResult r = render(scene, o, hooks);

  write_outputs(a.out, a.png, denoised ? r.denoised : r.last, o, meta);
  if (!a.average.empty()) write_exr(a.average, r.average, meta);
  const size_t pixels = size_t(o.film.width) * size_t(o.film.height);
  if (!a.timings.empty()) write_text_file_atomic(a.timings, timings_csv(r, pixels));
  if (a.stats) fmt::print("{}", stage_summary(r, pixels));
  // JSON sidecar beside the main output: configuration, scene, version and timings. The marker
  // key lets a later run tell its own sidecar from a user's JSON file of the same name.
  if (!sidecar.empty()) write_sidecar(sidecar, a.scene, config_json, r, pixels);
  if (!a.quiet) {
    double total = 0;
    for (double ms : r.frame_ms) total += ms;
    std::fprintf(stderr, "rendered %d frame(s) in %.1f ms (%.1f ms/frame)\n", o.render.frames, total,
                 total / double(r.frame_ms.size()));
  }
  return 0;
}

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
  fmt::print("emitters    {} (point lights {}, spot lights {}, distant lights {}, environment {})\n", lights.emitter_count(),
             scene.point_lights.size(), scene.spot_lights.size(), scene.distant_lights.size(),
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

}  // namespace rl::cli
