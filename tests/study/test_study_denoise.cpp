// The study harness after a denoiser: a configuration with denoise.method != none is scored on the
// denoised frames (the same images render() returns), and the metrics for what a denoiser changes:
// flicker (FLIP between consecutive frames) and relmse_lowpass (the error of 8x8 block means).
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "frame/render.h"
#include "image/image_io.h"
#include "image/metrics.h"
#include "scene/loader.h"
#include "study/images.h"
#include "study/runner.h"
#include "study/study_file.h"
#include "test_helpers.h"

using namespace rl;
using namespace rl::study;
namespace fs = std::filesystem;

namespace {

struct StudyRow {
  std::string config, denoise;
  int frame = 0;
  std::map<std::string, double> m;
};

std::vector<StudyRow> rows_of(const fs::path& results_json) {
  std::vector<StudyRow> out;
  const nlohmann::json j = nlohmann::json::parse(test::read_file(results_json));  // outlives the loop
  for (const auto& r : j.at("rows")) {
    StudyRow row;
    row.config = r.at("config").get<std::string>();
    row.denoise = r.at("options").at("denoise.method").get<std::string>();
    row.frame = r.at("frame").get<int>();
    for (const auto& [k, v] : r.at("metrics").items())
      if (!v.is_null()) row.m[k] = v.get<double>();
    out.push_back(row);
  }
  return out;
}

Image the_reference(const fs::path& out) {
  std::vector<fs::path> exr;
  for (const auto& e : fs::directory_iterator(out / "references"))
    if (e.path().extension() == ".exr") exr.push_back(e.path());
  REQUIRE(exr.size() == 1);
  return read_image(exr[0].string());
}

// The study's frames, rendered again through render(): the scored image of each frame (the
// denoised one when the configuration has a denoiser).
std::vector<Image> scored_frames(const Study& s, const Configuration& c) {
  const Scene scene = load_scene(s.scene_paths[0]);
  Options defaults;
  apply_scene_hints(defaults, scene.hints);
  const Options o = make_options(s, defaults, c, s.seeds[0]);
  std::vector<Image> frames;
  RenderHooks hooks;
  if (o.denoise.method == DenoiseMethod::none)
    hooks.on_frame = [&](int, const Image& img, double) { frames.push_back(img); };
  else
    hooks.on_denoised = [&](int, const Image& img) { frames.push_back(img); };
  render(scene, o, hooks);
  return frames;
}

// The configuration whose denoise.method is `method`.
Configuration config_with(const Study& s, const std::string& method) {
  for (const Configuration& c : expand(s))
    for (const auto& [k, v] : c.values)
      if (k == "denoise.method" && v == method) return c;
  FAIL("no configuration with denoise.method = " << method);
  return {};
}

const char* kBody = R"("base": {"integrator": "pt", "film.width": 32, "film.height": 24, "render.spp": 1},
    "axes": [{"key": "denoise.method", "values": ["none", "svgf"]}], "seeds": 1, "frames": 6,
    "reference": {"spp": 16}, )";

// Runs the pt study of kBody (denoise.method none and svgf) with `metrics` in a fresh folder; the
// study file is DIR/s.json, its outputs DIR/out.
fs::path run_denoise_study(const std::string& name, const std::string& metrics) {
  const fs::path d = test::fresh_temp_dir(name);
  std::ofstream(d / "s.json") << "{\"scenes\": [\"" << test::own_scene("cornell-box.pbrt") << "\"], " << kBody
                              << "\"metrics\": " << metrics << "}";
  StudyArgs a;
  a.study = (d / "s.json").string();
  a.out = (d / "out").string();
  a.quiet = true;
  REQUIRE(run_study(a) == 0);
  return d;
}

}  // namespace

TEST_SUITE("study") {
  TEST_CASE("a denoised configuration is scored on its denoised frames; flicker and relmse_lowpass as defined") {
    const fs::path d = run_denoise_study("study-denoise", R"(["time", "relmse", "relmse_lowpass", "flicker"])");
    const Study s = load_study((d / "s.json").string(), false);
    const Image ref = the_reference(d / "out");
    const auto rows = rows_of(d / "out/results.json");
    REQUIRE(rows.size() == 2);
    std::map<std::string, double> relmse, flicker;
    for (const StudyRow& r : rows) {
      CAPTURE(r.denoise);
      const auto frames = scored_frames(s, config_with(s, r.denoise));
      REQUIRE(frames.size() == 6);
      // The saved image is the scored one, and is what render() gives (its denoised frame for svgf).
      const Image saved = read_image((d / "out/images" / (r.config + ".exr")).string());
      CHECK(saved.pixels == frames.back().pixels);
      CHECK(r.m.at("relmse") == doctest::Approx(rel_mse(saved, ref)).epsilon(1e-12));
      CHECK(r.m.at("relmse_lowpass") == doctest::Approx(rel_mse_lowpass(saved, ref)).epsilon(1e-12));
      // flicker: the mean FLIP of frames 3, 4, 5 against their predecessors (the second half).
      double want = 0;
      for (int f = 3; f < 6; ++f) want += flip_metric(frames[size_t(f)], frames[size_t(f - 1)], OutputOptions{}) / 3;
      CHECK(r.m.at("flicker") == doctest::Approx(want).epsilon(1e-12));
      relmse[r.denoise] = r.m.at("relmse");
      flicker[r.denoise] = r.m.at("flicker");
    }
    // 1 spp path tracing, 6 frames: SVGF's accumulation and filter lower both a lot.
    CHECK(relmse["svgf"] < 0.5 * relmse["none"]);
    CHECK(flicker["svgf"] < 0.5 * flicker["none"]);
    fs::remove_all(d);
  }

  TEST_CASE("over time: flicker per frame from frame 1 (none at frame 0), against the previous scored frame") {
    const fs::path d = run_denoise_study("study-denoise-frames", R"(["relmse", "convergence", "flicker"])");
    const Study s = load_study((d / "s.json").string(), false);
    const auto rows = rows_of(d / "out/results.json");
    REQUIRE(rows.size() == 12);
    const auto frames = scored_frames(s, config_with(s, "svgf"));
    for (const StudyRow& r : rows) {
      CAPTURE(r.frame);
      CHECK(r.m.count("flicker") == (r.frame > 0 ? 1u : 0u));
      if (r.denoise == "svgf" && r.frame > 0)
        CHECK(r.m.at("flicker") ==
              doctest::Approx(flip_metric(frames[size_t(r.frame)], frames[size_t(r.frame - 1)], OutputOptions{})).epsilon(1e-12));
    }
    fs::remove_all(d);
  }
}
