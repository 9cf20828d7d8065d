#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>
#include <unistd.h>

#include "image/image_io.h"
#include "test_helpers.h"

using namespace rl;
using namespace rl::test;
namespace fs = std::filesystem;

namespace {
fs::path temp_dir(const char* name) { return fresh_temp_dir(std::string("cli-") + name); }
void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }
int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}
const char* kGoodScene = R"(Film "rgb" "integer xresolution" [8] "integer yresolution" [8]
Camera "perspective" "float fov" [60]
WorldBegin
AttributeBegin
AreaLightSource "diffuse" "rgb L" [1 1 1]
Shape "trianglemesh" "point3 P" [-1 -1 5  1 -1 5  1 1 5  -1 1 5] "integer indices" [0 1 2 0 2 3]
AttributeEnd
)";
}  // namespace

TEST_SUITE("cli") {
  TEST_CASE("render writes EXR, PNG and a JSON sidecar that carry the full configuration") {
    fs::path d = temp_dir("ok");
    write(d / "s.pbrt", kGoodScene);
    auto r = run_restir("render " + (d / "s.pbrt").string() + " -q --spp 2 --set path.max_depth=2 -o " +
                        (d / "o.exr").string() + " --png " + (d / "o.png").string());
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(fs::exists(d / "o.exr"));
    CHECK(fs::exists(d / "o.png"));
    CHECK(fs::exists(d / "o.json"));
    bool found = false;
    for (const auto& [k, v] : read_exr_metadata((d / "o.exr").string()))
      if (k == "restir.config") found = v.find("\"path.max_depth\":2") != std::string::npos;
    CHECK(found);
    // Nothing but the outputs: no temporary files left behind.
    int files = 0;
    for (const auto& e : fs::directory_iterator(d)) files += e.is_regular_file() ? 1 : 0;
    CHECK(files == 4);
    fs::remove_all(d);
  }

  // Issue 9: where the frame's time goes. Every integrator reports its stages; --timings has a
  // column per stage (0 where a frame did not run it: no temporal reuse on frame 0), then (issue
  // 48) the rays per pixel of each stage that traced any, by kind, and the frame's; the sidecar has
  // the counts.
  TEST_CASE("--timings writes each frame's stage times and rays per pixel; the sidecar the ray counts") {
    fs::path d = temp_dir("timings");
    write(d / "s.pbrt", kGoodScene);
    auto r = run_restir("render " + (d / "s.pbrt").string() + " -q --spp 1 --frames 3 --integrator restir-di --res 16x12 -o " +
                        (d / "o.exr").string() + " --timings " + (d / "t.csv").string());
    INFO(r.output);
    REQUIRE(r.status == 0);
    std::ifstream in(d / "t.csv");
    std::string header;
    std::getline(in, header);
    const std::string ms_columns = "frame,ms,primary_ms,light_tiles_ms,candidates_ms,temporal_ms,spatial_ms,shading_ms";
    CHECK(header.starts_with(ms_columns + ",primary_closest_px,primary_any_px,"));
    CHECK(header.ends_with(",closest_px,any_px"));
    CHECK(header.find("light_tiles_closest_px") == std::string::npos);  // no rays: no ray columns
    std::vector<std::string> names;
    std::stringstream hs(header);
    for (std::string cell; std::getline(hs, cell, ',');) names.push_back(cell);
    const auto column = [&](const std::string& n) { return size_t(std::find(names.begin(), names.end(), n) - names.begin()); };
    for (int f = 0; f < 3; ++f) {
      std::string line;
      REQUIRE(std::getline(in, line));
      std::vector<double> v;
      std::stringstream ss(line);
      for (std::string cell; std::getline(ss, cell, ',');) v.push_back(std::stod(cell));
      REQUIRE(v.size() == names.size());
      CHECK(v[0] == f);
      double stages = 0;
      for (size_t i = 2; i < 8; ++i) stages += v[i];
      CHECK(stages <= v[1] * 1.001 + 0.01);
      CHECK(stages > 0);
      CHECK((v[5] == 0) == (f == 0));  // temporal reuse needs a history
      CHECK(v[column("primary_closest_px")] == 1.0);  // a camera ray a pixel
      double closest = 0, any = 0;
      for (size_t i = 8; i + 2 < names.size(); i += 2) closest += v[i], any += v[i + 1];
      CHECK(v[column("closest_px")] == doctest::Approx(closest).epsilon(1e-3));
      CHECK(v[column("any_px")] == doctest::Approx(any).epsilon(1e-3));
      CHECK(any > 0);
    }
    const nlohmann::json side = nlohmann::json::parse(read_file(d / "o.json"));
    CHECK(side["pixels"] == 16 * 12);
    REQUIRE(side["stage_rays"].size() == 3);
    CHECK(side["stage_rays"][1]["primary"]["closest"] == 16 * 12);
    CHECK(side["stage_rays"][1]["primary"]["any"] == 0);
    fs::remove_all(d);
  }

  TEST_CASE("bad input gives one clear error line, a non-zero exit, and no output file") {
    fs::path d = temp_dir("bad");
    write(d / "good.pbrt", kGoodScene);
    write(d / "truncated.pbrt", std::string(kGoodScene).substr(0, 200));
    write(d / "unknown.pbrt", std::string("WorldBegin\nFrobnicate \"x\"\n"));
    write(d / "noply.pbrt", "WorldBegin\nShape \"plymesh\" \"string filename\" \"missing.ply\"\n");
    write(d / "noexr.pbrt", "WorldBegin\nLightSource \"infinite\" \"string filename\" \"missing.exr\"\n");
    const std::string good = (d / "good.pbrt").string(), out = (d / "out.exr").string();
    struct Case {
      std::string args, expect;
    } cases[] = {
        {"render " + (d / "truncated.pbrt").string() + " -o " + out, "truncated.pbrt"},
        {"render " + (d / "unknown.pbrt").string() + " -o " + out, "Frobnicate"},
        {"render " + (d / "noply.pbrt").string() + " -o " + out, "missing.ply"},
        {"render " + (d / "noexr.pbrt").string() + " -o " + out, "missing.exr"},
        {"render " + (d / "nonexistent.pbrt").string() + " -o " + out, "nonexistent.pbrt"},
        {"render " + good + " --set path.max_depth=deep -o " + out, "path.max_depth"},
        {"render " + good + " --set path.no_such_key=1 -o " + out, "path.no_such_key"},
        {"render " + good + " --integrator magic -o " + out, "magic"},
        {"render " + good + " --res 0x0 -o " + out, "film.width"},
        {"render " + good + " --res 100000x100000 -o " + out, "film.width"},
        {"render " + good + " --res 16000x16000 -o " + out, "too large"},
        {"render " + good + " --config " + (d / "missing.json").string() + " -o " + out, "missing.json"},
        {"compare " + (d / "a.exr").string() + " " + (d / "b.exr").string(), "a.exr"},
    };
    for (const auto& c : cases) {
      auto r = run_restir(c.args);
      CAPTURE(c.args);
      CAPTURE(r.output);
      CHECK(r.status != 0);
      CHECK(count_lines(r.output) == 1);
      CHECK(r.output.find("error") != std::string::npos);
      CHECK(r.output.find(c.expect) != std::string::npos);
      CHECK_FALSE(fs::exists(out));
    }
    fs::remove_all(d);
  }

  TEST_CASE("options lists every key; info and compare work") {
    auto r = run_restir("options");
    CHECK(r.status == 0);
    for (const auto& [k, v] : option_values(Options{})) CHECK_MESSAGE(r.output.find(k) != std::string::npos, k);
    auto info = run_restir("info " + shared_scene("cornell-box/scene-v4.pbrt"));
    CHECK(info.status == 0);
    CHECK(info.output.find("triangles") != std::string::npos);
    fs::path d = temp_dir("cmp");
    Image a(4, 4, Rgb(1)), b(4, 4, Rgb(1.5f));
    write_exr((d / "a.exr").string(), a);
    write_exr((d / "b.exr").string(), b);
    auto c = run_restir("compare --json " + (d / "a.exr").string() + " " + (d / "b.exr").string());
    CHECK(c.status == 0);
    CHECK(c.output.find("\"mse\": 0.25") != std::string::npos);
    fs::remove_all(d);
  }

  // A first ReSTIR render of a scene written for a path tracer: the Cornell box asks for maxdepth
  // 65 and many spp; restir-pt renders a 1-spp sequence at depth 64 and says so.
  TEST_CASE("restir-pt on the Cornell box: a sequence at 1 spp, the scene's depth fitted, each said once") {
    fs::path d = temp_dir("restir-defaults");
    const std::string scene = shared_scene("cornell-box/scene-v4.pbrt");
    auto r = run_restir("render " + scene + " --integrator restir-pt --res 24x24 -o " + (d / "o.exr").string());
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(r.output.find("note: restir-pt renders 1 to 64 bounces: path.max_depth 65 (from the scene) becomes 64") != std::string::npos);
    CHECK(r.output.find("note: restir-pt renders a sequence: 1 sample per pixel per frame, 16 frames") != std::string::npos);
    CHECK(r.output.find("16 frame(s)") != std::string::npos);
    // Not a terminal (a pipe): frame lines without the escape codes that clear a progress bar.
    CHECK(r.output.find("frame 15: ") != std::string::npos);
    CHECK(r.output.find('\033') == std::string::npos);
    CHECK(r.output.find('\r') == std::string::npos);
    // Many spp in one frame, asked for: rendered, with a warning even under -q.
    auto w = run_restir("render " + scene + " -q --integrator restir-di --res 16x16 --spp 4 --frames 1 -o " + (d / "w.exr").string());
    INFO(w.output);
    CHECK(w.status == 0);
    CHECK(w.output.find("warning: restir-di with 4 spp in 1 frame") != std::string::npos);
    // An explicit depth out of range: refused, saying what to set.
    auto e = run_restir("render " + scene + " -q --integrator restir-pt --set path.max_depth=65 -o " + (d / "e.exr").string());
    CHECK(e.status != 0);
    CHECK(e.output.find("set path.max_depth to a value in [1, 64]") != std::string::npos);
    CHECK(!fs::exists(d / "e.exr"));
    fs::remove_all(d);
  }
}
