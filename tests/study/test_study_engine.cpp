// Studies run on another backend through --set (issue 48: the GPU as the study engine) and what a
// frame costs besides time (the metric cost: rays and buffers per pixel, issues 45 and 48).
#include <doctest/doctest.h>

#include <map>
#include <set>
#include <string>
#include <vector>

#include "frame/gbuffer.h"
#include "image/image_io.h"
#include "study/runner.h"
#include "study/study_file.h"
#include "study_files.h"

using namespace rl;
using namespace rl::study;
using namespace rl::test::study_files;

TEST_SUITE("study") {
  // Issue 48: the GPU as the study engine. --set render.backend=cuda runs a study and its
  // references on the GPU; here its host twin (cpu-bvh), which takes the same route.
  TEST_CASE("--set puts options over the base of every configuration and its references; an axis still sweeps") {
    fs::path d = temp_dir("set");
    write(d / "s.json", study_json(R"("base": {"integrator": "restir-di", "film.width": 24, "film.height": 16, "render.spp": 1},
        "axes": [{"key": "di.spatial_radius", "values": [0, 10]}], "seeds": 1, "frames": 2,
        "metrics": ["time", "relmse"], "reference": {"spp": 4})"));
    StudyArgs a;
    a.study = (d / "s.json").string();
    a.out = (d / "out").string();
    a.quiet = true;
    a.sets = {"render.backend=cpu-bvh", "film.width=20", "di.spatial_radius=5"};
    REQUIRE(run_study(a) == 0);
    CsvTable t = read_csv(d / "out/results.csv");
    REQUIRE(t.rows.size() == 2);
    std::set<std::string> radii;
    for (const auto& r : t.rows) radii.insert(r[size_t(t.col("di.spatial_radius"))]);
    CHECK(radii == std::set<std::string>{"0", "10"});  // the axis, not --set's 5
    int references = 0;
    for (const auto& e : fs::directory_iterator(d / "out/references")) {
      if (e.path().extension() != ".exr") continue;
      ++references;
      CHECK(read_image(e.path().string()).width == 20);
      std::string config;
      for (const auto& [k, v] : read_exr_metadata(e.path().string()))
        if (k == "restir.config") config = v;
      CHECK(config.find("\"render.backend\":\"cpu-bvh\"") != std::string::npos);  // the reference on the study's backend
    }
    CHECK(references == 1);
    const auto error_with = [&](std::vector<std::string> sets) {
      a.sets = std::move(sets);
      try {
        run_study(a);
      } catch (const StudyError& e) {
        return std::string(e.what());
      }
      return std::string();
    };
    const std::string unknown = error_with({"render.sp=1"});
    CHECK(unknown.find("--set") != std::string::npos);
    CHECK(unknown.find("render.sp") != std::string::npos);
    CHECK(error_with({"render.spp"}).find("expected KEY=VALUE") != std::string::npos);
    CHECK(error_with({"render.backend=gpu"}).find("render.backend") != std::string::npos);
    fs::remove_all(d);
  }

  // Issue 45's cost ladder needs rays and memory per pixel beside the time.
  TEST_CASE("the metric cost: rays per pixel by kind and buffers per pixel, per frame in a study over time") {
    fs::path d = temp_dir("cost");
    write(d / "s.json", study_json(R"("base": {"integrator": "restir-di", "film.width": 24, "film.height": 16, "render.spp": 1},
        "axes": [{"key": "di.bsdf_candidates", "values": [0, 2]}], "seeds": 1, "frames": 3,
        "metrics": ["time", "cost", "convergence"], "reference": {"spp": 4})"));
    StudyArgs a;
    a.study = (d / "s.json").string();
    a.out = (d / "out").string();
    a.quiet = true;
    REQUIRE(run_study(a) == 0);
    CsvTable t = read_csv(d / "out/results.csv");
    REQUIRE(t.rows.size() == 6);  // 2 configurations x 3 frames
    std::map<std::pair<std::string, std::string>, double> rays, closest;  // (BSDF candidates, frame) -> rays_px, closest_px
    for (const auto& r : t.rows) {
      const double c = std::stod(r[size_t(t.col("closest_px"))]), y = std::stod(r[size_t(t.col("any_px"))]);
      CHECK(c >= 1.0);  // a camera ray a pixel at least
      CHECK(y > 0);
      CHECK(std::stod(r[size_t(t.col("rays_px"))]) == doctest::Approx(c + y));
      CHECK(std::stod(r[size_t(t.col("bytes_px"))]) > 2.0 * sizeof(GSurface));
      rays[{r[size_t(t.col("di.bsdf_candidates"))], r[size_t(t.col("frame"))]}] = c + y;
      closest[{r[size_t(t.col("di.bsdf_candidates"))], r[size_t(t.col("frame"))]}] = c;
    }
    for (const char* f : {"0", "1", "2"}) {  // at most a closest-hit ray per BSDF candidate (none where the sample fails)
      CHECK(closest[{"2", f}] - closest[{"0", f}] > 0.5);
      CHECK(closest[{"2", f}] - closest[{"0", f}] <= 2.0);
    }
    CHECK(rays[{"0", "1"}] > rays[{"0", "0"}]);  // temporal reuse's shadow rays, from frame 1 on
    fs::remove_all(d);
  }
}
