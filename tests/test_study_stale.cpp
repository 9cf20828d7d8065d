// Stale study rows (issue #8): a row's identity includes the content of every file its scene was
// read from, so editing an included file and rerunning into the same --out recomputes the row and
// the report says so.
#include <doctest/doctest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "study/runner.h"
#include "test_helpers.h"

using namespace rl;
namespace fs = std::filesystem;

namespace {
std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
std::string emitter(float l) {
  return "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [" + std::to_string(l) + " 1 1]\n"
         "Shape \"trianglemesh\" \"point3 P\" [-1 -1 5  1 -1 5  1 1 5  -1 1 5] \"integer indices\" [0 1 2 0 2 3]\n"
         "AttributeEnd\n";
}
}  // namespace

TEST_SUITE("study_stale") {
  TEST_CASE("editing a file the scene includes makes its rows stale: recomputed, and the report says so") {
    fs::path d = fs::temp_directory_path() / ("restir-stale-" + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    std::ofstream(d / "s.pbrt") << "Film \"rgb\" \"integer xresolution\" [8] \"integer yresolution\" [8]\n"
                                   "Camera \"perspective\" \"float fov\" [60]\nWorldBegin\nInclude \"light.pbrt\"\n";
    std::ofstream(d / "light.pbrt") << emitter(1);
    std::ofstream(d / "st.json") << "{\"scenes\": [\"" + (d / "s.pbrt").string() +
                                        "\"], \"base\": {\"integrator\": \"pt\", \"render.spp\": 1}, \"seeds\": 1, "
                                        "\"metrics\": [\"relmse\"], \"reference\": {\"spp\": 2}}";
    study::StudyArgs a;
    a.study = (d / "st.json").string();
    a.out = (d / "out").string();
    a.quiet = true;
    REQUIRE(study::run_study(a) == 0);
    const std::string first = slurp(d / "out/results.csv");
    CHECK(slurp(d / "out/report.html").find("were stale") == std::string::npos);

    std::ofstream(d / "light.pbrt") << emitter(4);  // only the included file changes
    auto r = test::run_restir("study " + a.study + " --out " + a.out);
    INFO(r.output);
    CHECK(r.status == 0);
    CHECK(r.output.find("1 to run") != std::string::npos);
    CHECK(r.output.find("older inputs") != std::string::npos);
    CHECK(slurp(d / "out/report.html").find("1 stored row(s) were stale") != std::string::npos);
    CHECK(slurp(d / "out/results.csv") != first);
    // The stale row is gone from the store: a third run has nothing stale and nothing to run.
    auto again = test::run_restir("study " + a.study + " --out " + a.out);
    CHECK(again.output.find("0 to run") != std::string::npos);
    CHECK(again.output.find("older inputs") == std::string::npos);
    fs::remove_all(d);
  }
}
