// Stale study rows (issue #8): a row's identity includes the content of every file its scene was
// read from, so editing an included file and rerunning into the same --out recomputes the row and
// the report says so.
#include <doctest/doctest.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/build_info.h"
#include "study/runner.h"
#include "test_helpers.h"

using namespace rl;
namespace fs = std::filesystem;

namespace {
std::string emitter(float l) {
  return "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [" + std::to_string(l) + " 1 1]\n"
         "Shape \"trianglemesh\" \"point3 P\" [-1 -1 5  1 -1 5  1 1 5  -1 1 5] \"integer indices\" [0 1 2 0 2 3]\n"
         "AttributeEnd\n";
}
}  // namespace

TEST_SUITE("study_stale") {
  // The binary's version in a row's identity is the build id, a hash of every source file, made at
  // each build: rows and references of an older binary are recomputed (issue #8).
  TEST_CASE("the build id is the hash of the sources the binary was built from, and changes with them") {
    auto id_of = [](const fs::path& src, const fs::path& out) {
      const std::string cmd = std::string(RESTIR_CMAKE) + " -DSRC=" + src.string() + " -DOUT=" + out.string() +
                              " -DVERSION=" RESTIR_PROJECT_VERSION " -P " RESTIR_SOURCE_DIR "/cmake/build_id.cmake";
      REQUIRE(std::system(cmd.c_str()) == 0);
      return test::read_file(out);
    };
    fs::path d = fs::temp_directory_path() / ("restir-buildid-" + std::to_string(::getpid()));
    fs::remove_all(d);
    // The id this binary carries is the one the script computes from today's source tree.
    const std::string here = id_of(RESTIR_SOURCE_DIR, d / "here.h");
    CHECK(here.find(std::string("\"") + build_id() + "\"") != std::string::npos);
    CHECK(std::string(build_id()).starts_with(RESTIR_PROJECT_VERSION "+src."));
    // A toy tree: same sources, same id and the header is not rewritten; one edited line, new id.
    fs::create_directories(d / "src/core");
    std::ofstream(d / "src/core/a.cpp") << "int a() { return 1; }\n";
    const std::string first = id_of(d, d / "id.h");
    const auto stamp = fs::last_write_time(d / "id.h");
    CHECK(id_of(d, d / "id.h") == first);
    CHECK(fs::last_write_time(d / "id.h") == stamp);
    std::ofstream(d / "src/core/a.cpp") << "int a() { return 2; }\n";
    CHECK(id_of(d, d / "id.h") != first);
    fs::remove_all(d);
  }

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
    const std::string first = test::read_file(d / "out/results.csv");
    CHECK(test::read_file(d / "out/report.html").find("were stale") == std::string::npos);

    std::ofstream(d / "light.pbrt") << emitter(4);  // only the included file changes
    auto r = test::run_restir("study " + a.study + " --out " + a.out);
    INFO(r.output);
    CHECK(r.status == 0);
    CHECK(r.output.find("1 to run") != std::string::npos);
    CHECK(r.output.find("older inputs") != std::string::npos);
    CHECK(test::read_file(d / "out/report.html").find("1 stored row(s) were stale") != std::string::npos);
    CHECK(test::read_file(d / "out/results.csv") != first);
    // Made stale again, then --merge (which renders nothing): the old row stays in the store (not
    // in the report: it is of older inputs), the merge says the job is missing, and a run
    // recomputes and replaces it.
    const std::string second = test::read_file(d / "out/results.csv");
    std::ofstream(d / "light.pbrt") << emitter(2);
    auto merged = test::run_restir("study " + a.study + " --out " + a.out + " --merge");
    CHECK(merged.status == 1);
    CHECK(merged.output.find("1 of 1 job(s) missing") != std::string::npos);
    CHECK(test::read_file(d / "out/results.csv") == second);
    auto rerun = test::run_restir("study " + a.study + " --out " + a.out);
    CHECK(rerun.status == 0);
    CHECK(rerun.output.find("older inputs") != std::string::npos);
    CHECK(test::read_file(d / "out/results.csv") != second);
    // The stale row is gone from the store: a third run has nothing stale and nothing to run.
    auto again = test::run_restir("study " + a.study + " --out " + a.out);
    CHECK(again.output.find("0 to run") != std::string::npos);
    CHECK(again.output.find("older inputs") == std::string::npos);
    fs::remove_all(d);
  }
}
