// restir compare (FLIP, --error-map, --crop, the different-integrals warning), restir tonemap and
// restir options PREFIX, through the binary.
#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "frame/options.h"
#include "image/image_io.h"
#include "image/metrics.h"
#include "image/tonemap.h"
#include "study/images.h"
#include "test_helpers.h"

using namespace rl;
using namespace rl::test;
namespace fs = std::filesystem;

namespace {
fs::path fresh_dir(const char* name) { return fresh_temp_dir(std::string("cli-img-") + name); }
// A smooth gradient and the same with a bright square: a difference FLIP sees.
Image gradient(int w, int h, bool square) {
  Image img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool in = square && x >= w / 2 && x < w / 2 + 8 && y >= 4 && y < 12;
      img.at(x, y) = in ? Rgb(3.0f) : Rgb(0.1f + 0.8f * float(x) / float(w), 0.3f, 0.5f * float(y) / float(h));
    }
  return img;
}
double json_number(const std::string& out, const std::string& key) {
  const size_t at = out.find("\"" + key + "\": ");
  REQUIRE(at != std::string::npos);
  return std::strtod(out.c_str() + at + key.size() + 4, nullptr);
}
}  // namespace

TEST_SUITE("cli") {
  TEST_CASE("compare: FLIP as a study computes it, an error map with its scale, a crop") {
    fs::path d = fresh_dir("flip");
    const Image test = gradient(48, 32, true), ref = gradient(48, 32, false);
    write_exr((d / "t.exr").string(), test);
    write_exr((d / "r.exr").string(), ref);
    auto c = run_restir("compare --json " + (d / "t.exr").string() + " " + (d / "r.exr").string() + " --error-map " +
                        (d / "e.png").string());
    INFO(c.output);
    REQUIRE(c.status == 0);
    // Without a recorded configuration, the default tone mapping: the study's flip_metric with it.
    const double flip = study::flip_metric(test, ref, Options{}.output);
    CHECK(flip > 0.001);
    CHECK(json_number(c.output, "flip") == doctest::Approx(flip).epsilon(1e-6));
    CHECK(json_number(c.output, "mse") == doctest::Approx(mse(test, ref)).epsilon(1e-6));
    // The map above its scale bar: taller than the image, as wide; bright where the square is.
    const Image map = read_image((d / "e.png").string());
    CHECK(map.width == 64);  // the scale bar is at least 64 pixels wide
    CHECK(map.height == 32 + study::error_scale_bar(64).height);
    CHECK(map.at(28, 8)[0] > map.at(2, 28)[0] + 0.2f);
    // A crop outside the square sees no difference; one inside it sees more than the whole.
    auto out = run_restir("compare --json --crop 0,16,16,16 " + (d / "t.exr").string() + " " + (d / "r.exr").string());
    CHECK(json_number(out.output, "mse") == doctest::Approx(0.0));
    auto in = run_restir("compare --json --crop 24,4,8,8 " + (d / "t.exr").string() + " " + (d / "r.exr").string());
    CHECK(json_number(in.output, "mse") > 2 * json_number(c.output, "mse"));
    auto bad = run_restir("compare --crop 40,0,16,16 " + (d / "t.exr").string() + " " + (d / "r.exr").string());
    CHECK(bad.status == 1);
    CHECK(bad.output.find("lies outside the test image (48x32)") != std::string::npos);
    // The error map may not replace an input.
    auto clobber = run_restir("compare " + (d / "t.exr").string() + " " + (d / "r.exr").string() + " --error-map " +
                              (d / "t.exr").string());
    CHECK(clobber.status != 0);
    CHECK(fs::file_size(d / "t.exr") > 0);
    fs::remove_all(d);
  }

  TEST_CASE("compare warns when the images estimate different integrals; tonemap writes the PNG render would") {
    fs::path d = fresh_dir("integrals");
    const std::string scene = shared_scene("cornell-box/scene-v4.pbrt");
    auto pt = run_restir("render " + scene + " -q --res 16x16 --spp 2 -o " + (d / "pt.exr").string() + " --png " +
                         (d / "pt.png").string());
    auto di = run_restir("render " + scene + " -q --res 16x16 --integrator restir-di --frames 2 -o " + (d / "di.exr").string());
    auto pt2 = run_restir("render " + scene + " -q --res 16x16 --spp 1 --seed 3 -o " + (d / "pt2.exr").string());
    REQUIRE((pt.status == 0 && di.status == 0 && pt2.status == 0));
    auto c = run_restir("compare " + (d / "di.exr").string() + " " + (d / "pt.exr").string());
    CHECK(c.status == 0);
    CHECK(c.output.find("warning: compare: the images estimate different integrals") != std::string::npos);
    CHECK(c.output.find("direct light only (restir-di") != std::string::npos);
    auto same = run_restir("compare " + (d / "pt2.exr").string() + " " + (d / "pt.exr").string());
    CHECK(same.output.find("warning") == std::string::npos);
    // A ReSTIR PT sequence against the path tracer at the same depth: the same integral, no warning.
    auto rp = run_restir("render " + scene + " -q --res 16x16 --integrator restir-pt --frames 2 -o " + (d / "rp.exr").string());
    REQUIRE(rp.status == 0);
    auto pt64 = run_restir("render " + scene + " -q --res 16x16 --spp 1 --set path.max_depth=64 -o " + (d / "pt64.exr").string());
    auto restir_vs_pt = run_restir("compare " + (d / "rp.exr").string() + " " + (d / "pt64.exr").string());
    INFO(restir_vs_pt.output);
    CHECK(restir_vs_pt.output.find("warning") == std::string::npos);
    // tonemap: the same pixels as render's --png (the tone mapping read from the EXR header).
    auto t = run_restir("tonemap " + (d / "pt.exr").string() + " " + (d / "again.png").string());
    REQUIRE(t.status == 0);
    const Image a = read_image((d / "pt.png").string()), b = read_image((d / "again.png").string());
    CHECK(mse(a, b) == 0.0);
    auto lin = run_restir("tonemap " + (d / "pt.exr").string() + " " + (d / "lin.png").string() + " --set output.tonemap=linear");
    REQUIRE(lin.status == 0);
    CHECK(mse(read_image((d / "lin.png").string()), a) > 0);
    auto notout = run_restir("tonemap " + (d / "pt.exr").string() + " " + (d / "x.png").string() + " --set path.max_depth=3");
    CHECK(notout.status == 2);
    fs::remove_all(d);
  }

  TEST_CASE("options PREFIX lists those keys only, and a misspelt prefix names the near one") {
    auto r = run_restir("options pt.spatial");
    REQUIRE(r.status == 0);
    CHECK(r.output.find("pt.spatial_radius") != std::string::npos);
    CHECK(r.output.find("di.spatial_radius") == std::string::npos);
    CHECK(r.output.find("Integrators:") == std::string::npos);
    auto bad = run_restir("options pt.spatail");
    CHECK(bad.status == 1);
    CHECK(bad.output.find("did you mean 'pt.spatial'?") != std::string::npos);
    auto typo = run_restir("render x.pbrt -o x.exr --set render.sp=2");
    CHECK(typo.status != 0);
  }

  TEST_CASE("a pbrt Integrator or Sampler restir-lab does not have is a warning that says what is rendered") {
    fs::path d = fresh_dir("pbrt-names");
    std::ofstream(d / "s.pbrt") << "Integrator \"bdpt\" \"integer maxdepth\" [3]\nSampler \"pmj02bn\" \"integer pixelsamples\" [2]\n"
                                   "Camera \"perspective\"\nWorldBegin\nLightSource \"point\" \"rgb I\" [1 1 1]\nShape \"sphere\"\n";
    auto r = run_restir("render " + (d / "s.pbrt").string() + " -q --res 8x8 -o " + (d / "o.exr").string());
    INFO(r.output);
    CHECK(r.status == 0);
    CHECK(r.output.find("s.pbrt:1: warning: Integrator \"bdpt\" is not supported: rendered with the options' integrator") != std::string::npos);
    CHECK(r.output.find("s.pbrt:2: warning: Sampler \"pmj02bn\": rendered with restir-lab's own sample positions") != std::string::npos);
    std::ofstream(d / "p.pbrt") << "Integrator \"path\"\nSampler \"independent\"\nCamera \"perspective\"\nWorldBegin\n"
                                   "LightSource \"point\" \"rgb I\" [1 1 1]\nShape \"sphere\"\n";
    auto q = run_restir("render " + (d / "p.pbrt").string() + " -q --res 8x8 -o " + (d / "p.exr").string());
    CHECK(q.output.find("warning") == std::string::npos);
    fs::remove_all(d);
  }

  TEST_CASE("--frame-dir --frame-format png writes tone-mapped frames; --stats prints each stage's share") {
    fs::path d = fresh_dir("frames");
    const std::string scene = shared_scene("cornell-box/scene-v4.pbrt");
    auto r = run_restir("render " + scene + " -q --integrator restir-di --res 16x16 --frames 3 --frame-dir " + (d / "f").string() +
                        " --frame-format png --png " + (d / "last.png").string() + " --stats");
    INFO(r.output);
    REQUIRE(r.status == 0);
    for (int f = 0; f < 3; ++f) CHECK(fs::exists(d / "f" / ("frame_000" + std::to_string(f) + ".png")));
    CHECK(!fs::exists(d / "f" / "frame_0000.exr"));
    // The last frame's PNG is the --png output, pixel for pixel.
    CHECK(mse(read_image((d / "f" / "frame_0002.png").string()), read_image((d / "last.png").string())) == 0.0);
    CHECK(r.output.find("candidates") != std::string::npos);
    CHECK(r.output.find("temporal") != std::string::npos);
    CHECK(r.output.find("(ran in 2 of 3 frames)") != std::string::npos);  // no temporal reuse on frame 0
    CHECK(r.output.find("closest/px") != std::string::npos);            // and the rays each stage traced
    CHECK(r.output.find("bytes per pixel") != std::string::npos);       // and the integrator's buffers
    CHECK(r.output.find("frame ") != std::string::npos);
    auto bad = run_restir("render " + scene + " -q --res 8x8 --frame-dir " + (d / "g").string() + " --frame-format gif");
    CHECK(bad.status == 2);
    fs::remove_all(d);
  }
}
