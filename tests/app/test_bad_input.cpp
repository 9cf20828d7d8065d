// The hostile-input battery (issue #8): every case runs the `restir` binary on small files in a
// fresh folder and asserts the exit status, exactly one "error:" line that names where the
// problem is (file:line and the parameter, or the flag and path), nothing else but warnings,
// every input left byte-for-byte unchanged and no output or temporary file left behind.
// Positive controls check that the guards do not refuse what is fine.
#include <doctest/doctest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "bad_input_cases.h"
#include "test_helpers.h"

using namespace rl;
using namespace rl::test;
namespace fs = std::filesystem;

namespace {

fs::path fresh_dir(const std::string& tag) { return fresh_temp_dir("bad-" + tag); }

// Every regular file and folder under d, relative, with the files' contents.
std::map<std::string, std::string> snapshot(const fs::path& d) {
  std::map<std::string, std::string> m;
  for (const auto& e : fs::recursive_directory_iterator(d)) {
    std::string rel = fs::relative(e.path(), d).string();
    m[rel] = e.is_regular_file() ? test::read_file(e.path()) : std::string("<dir>");
  }
  return m;
}

std::string substitute(std::string s, const std::string& dir) {
  for (size_t at; (at = s.find("{d}")) != std::string::npos;) s.replace(at, 3, dir);
  return s;
}

std::vector<std::string> lines_of(const std::string& s) {
  std::vector<std::string> v;
  std::istringstream in(s);
  for (std::string l; std::getline(in, l);) v.push_back(l);
  return v;
}

void run_case(const BadCase& c, const fs::path& d) {
  for (const auto& [name, text] : c.files) {
    fs::path p = d / name;
    if (name.back() == '/') {
      fs::create_directories(p);
      continue;
    }
    fs::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << text;
  }
  const auto before = snapshot(d);
  const std::string args = substitute(c.args, d.string());
  auto r = run_restir(args);
  CAPTURE(c.name);
  CAPTURE(args);
  CAPTURE(r.output);
  CHECK(r.status == c.status);
  int errors = 0;
  std::string error_line;
  for (const std::string& l : lines_of(r.output)) {
    if (l.starts_with("error: ")) {
      ++errors;
      error_line = l;
    } else {
      CHECK_MESSAGE(l.find("warning: ") != std::string::npos, "a line that is neither the error nor a warning: " << l);
    }
  }
  CHECK(errors == 1);
  for (const std::string& e : c.expect)
    CHECK_MESSAGE(error_line.find(substitute(e, d.string())) != std::string::npos, "error line lacks: " << e);
  // Nothing written, nothing destroyed, no temporary file.
  CHECK(snapshot(d) == before);
}

}  // namespace

TEST_SUITE("bad_input") {
  TEST_CASE("the hostile-input battery: one error line with its location, nothing written or destroyed") {
    const std::vector<BadCase> cases = bad_input_cases();
    MESSAGE("hostile cases: " << cases.size());
    CHECK(cases.size() >= 150);
    fs::path root = fresh_dir("battery");
    for (size_t i = 0; i < cases.size(); ++i) {
      fs::path d = root / std::to_string(i);
      fs::create_directories(d);
      run_case(cases[i], d);
    }
    fs::remove_all(root);
  }

  TEST_CASE("positive controls: what is valid still renders, with warnings where due") {
    fs::path d = fresh_dir("ok");
    const std::string s = (d / "s.pbrt").string();
    std::ofstream(d / "s.pbrt") << good_scene();
    auto render = [&](const std::string& extra) { return run_restir("render -q --spp 1 " + s + " " + extra); };

    SUBCASE("a plain render, twice into the same outputs (our own sidecar is replaced)") {
      for (int i = 0; i < 2; ++i) {
        auto r = render("-o " + (d / "o.exr").string() + " --png " + (d / "o.png").string());
        INFO(r.output);
        CHECK(r.status == 0);
      }
      CHECK(test::read_file(d / "o.json").find("restir_sidecar") != std::string::npos);
    }
    SUBCASE("a missing output folder is created before rendering, for every output") {
      auto r = render("-o " + (d / "out/a/o.exr").string() + " --timings " + (d / "t/times.csv").string());
      INFO(r.output);
      CHECK(r.status == 0);
      CHECK(fs::exists(d / "out/a/o.exr"));
      CHECK(fs::exists(d / "out/a/o.json"));
      CHECK(fs::exists(d / "t/times.csv"));
    }
    SUBCASE("a sidecar of an earlier version (no marker) may be replaced") {
      std::ofstream(d / "o.json") << R"({"version": "0.1.0", "scene": "x", "config": {}, "frame_ms": [1]})";
      auto r = render("-o " + (d / "o.exr").string());
      INFO(r.output);
      CHECK(r.status == 0);
    }
    SUBCASE("a UTF-8 byte-order mark is skipped") {
      std::ofstream(d / "bom.pbrt") << "\xEF\xBB\xBF" << good_scene();
      auto r = run_restir("render -q --spp 1 " + (d / "bom.pbrt").string() + " -o " + (d / "o.exr").string());
      INFO(r.output);
      CHECK(r.status == 0);
    }
    SUBCASE("a scene without lights renders black, with a warning") {
      std::ofstream(d / "dark.pbrt") << "Film \"rgb\" \"integer xresolution\" [4] \"integer yresolution\" [4]\nWorldBegin\n"
                                        "Shape \"sphere\" \"float radius\" [1]\n";
      auto r = run_restir("render -q --spp 1 " + (d / "dark.pbrt").string() + " -o " + (d / "o.exr").string());
      INFO(r.output);
      CHECK(r.status == 0);
      CHECK(r.output.find("warning: the scene has no light source") != std::string::npos);
    }
    SUBCASE("boundary values are accepted: reflectance 0 and 1, roughness 0, scale 0") {
      std::ofstream(d / "edge.pbrt") << good_scene() << "Material \"diffuse\" \"rgb reflectance\" [0 1 1]\n"
                                     << "Material \"conductor\" \"float roughness\" [0]\n"
                                     << "LightSource \"point\" \"rgb I\" [1 1 1] \"float scale\" [0]\n";
      auto r = run_restir("render -q --spp 1 " + (d / "edge.pbrt").string() + " -o " + (d / "o.exr").string());
      INFO(r.output);
      CHECK(r.status == 0);
    }
    SUBCASE("help and version exit 0") {
      CHECK(run_restir("--help").status == 0);
      const CommandResult v = run_restir("--version");
      CHECK(v.status == 0);
      CHECK(v.output.find(RESTIR_PROJECT_VERSION) == 0);       // the build id first
      CHECK(v.output.find("cuda backend: ") != std::string::npos);  // then whether render.backend=cuda can run
      CHECK(run_restir("render --help").status == 0);
    }
    fs::remove_all(d);
  }
}
