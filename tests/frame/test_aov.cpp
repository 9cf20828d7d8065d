// AOVs (frame/aov.h) on the analytic card scene (tests/support/denoise_scene.h): linear depth,
// normal, albedo, surface id and motion vectors against their closed forms, and the EXR layers
// that `restir render --aov-dir` writes.
#include <doctest/doctest.h>

#include <ImfChannelList.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>

#include <cmath>
#include <fstream>

#include "denoise_scene.h"
#include "frame/aov.h"
#include "frame/render.h"
#include "image/image_io.h"
#include "scene/loader.h"
#include "test_helpers.h"

using namespace rl;
using namespace rl::test;

namespace {

Options card_options() {
  const Scene probe = card_scene();
  Options o = options_for(probe, {"render.spp=1", "path.max_depth=1"});
  return o;
}

// Pixel columns well inside the card (left) and the background (right), away from the edge.
constexpr int kCardX = 10, kBackgroundX = 54;

}  // namespace

TEST_SUITE("aov") {
  TEST_CASE("depth, normal, albedo and surface id equal the card scene's analytic values") {
    const Scene scene = card_scene();
    const Options o = card_options();
    FrameRenderer r(scene, o);
    r.request_aovs(true);
    Image img;
    r.render_frame(card_camera(0), 1, img, nullptr);
    const Aovs& a = r.aovs();
    REQUIRE(a.width == kCardWidth);
    REQUIRE(a.height == kCardHeight);
    for (int y = 0; y < a.height; ++y)
      for (int x : {0, kCardX, kCardWidth / 2 - 1, kCardWidth / 2, kBackgroundX, kCardWidth - 1}) {
        const size_t i = a.index(x, y);
        const bool card = x < kCardWidth / 2;
        CAPTURE(x);
        CAPTURE(y);
        REQUIRE(a.valid(i));
        // Linear view depth, not distance: the same on the whole plane.
        CHECK(a.depth[i] == doctest::Approx(card ? kCardZ : kBackgroundZ).epsilon(1e-5));
        CHECK(a.normal[i].z == doctest::Approx(-1).epsilon(1e-6));
        CHECK(std::fabs(a.normal[i].x) < 1e-6f);
        CHECK(a.albedo[i].x == doctest::Approx(card ? 0.6f : 0.3f));
        CHECK(a.albedo[i].z == doctest::Approx(card ? 0.4f : 0.7f));
        CHECK(a.emission[i].x == 0.0f);
        CHECK(a.motion[i].x == 0.0f);  // the first frame: no previous camera
        if (x != kCardWidth / 2 - 1 && x != kCardWidth / 2) CHECK(a.depth_gradient[i] < 1e-4f);
      }
    // The occlusion edge: the two columns beside it are on different shapes; their derivative is
    // the one-sided one (0 on a plane facing the camera), not the jump of 7 across the edge.
    const size_t l = a.index(kCardWidth / 2 - 1, 20), rr = a.index(kCardWidth / 2, 20);
    CHECK(a.surface_id[l] != a.surface_id[rr]);
    CHECK(a.surface_id[l] == a.surface_id[a.index(0, 0)]);
    CHECK(a.depth_gradient[l] < 1e-4f);
  }

  TEST_CASE("motion is zero for a still camera and the analytic parallax shift for a translated one") {
    const Scene scene = card_scene();
    FrameRenderer r(scene, card_options());
    r.request_aovs(true);
    Image img;
    r.render_frame(card_camera(0), 3, img, nullptr);
    r.render_frame(card_camera(0), 3, img, nullptr);
    const Aovs& still = r.aovs();
    for (size_t i = 0; i < still.motion.size(); ++i) {
      REQUIRE(still.motion[i].x == 0.0f);
      REQUIRE(still.motion[i].y == 0.0f);
    }
    const float dx = 0.5f;
    r.render_frame(card_camera(dx), 3, img, nullptr);
    const Aovs& moved = r.aovs();
    for (int y = 0; y < kCardHeight; y += 7) {
      const size_t c = moved.index(kCardX, y), b = moved.index(kBackgroundX, y);
      CHECK(moved.motion[c].x == doctest::Approx(card_shift(dx, kCardZ)).epsilon(1e-3));
      CHECK(moved.motion[b].x == doctest::Approx(card_shift(dx, kBackgroundZ)).epsilon(1e-3));
      CHECK(std::fabs(moved.motion[c].y) < 1e-3f);
      CHECK(std::fabs(moved.motion[b].y) < 1e-3f);
    }
    CHECK(card_shift(dx, kCardZ) == doctest::Approx(6.93).epsilon(1e-2));  // the closed form itself
  }

  TEST_CASE("an animated object's motion vectors follow its motion (GMotion), a still camera's stay 0") {
    // The card moves +0.1 along x per frame (linear keys 0 -> 1 over 10 frames); the background stays.
    const auto dir = fresh_temp_dir("aov-moving");
    std::ofstream(dir / "move.json") << R"({"keys": [{"frame": 0, "translate": [0, 0, 0]}, {"frame": 10, "translate": [1, 0, 0]}]})";
    std::ofstream(dir / "moving.pbrt") << R"(LookAt 0 0 0  0 0 1  0 1 0
Camera "perspective" "float fov" 60
Film "rgb" "integer xresolution" 64 "integer yresolution" 48
WorldBegin
LightSource "infinite" "rgb L" [1 1 1]
AttributeBegin
  Attribute "shape" "string animation" "move.json"
  Shape "trianglemesh" "point3 P" [-20 -20 3  0 -20 3  0 20 3  -20 20 3] "integer indices" [0 1 2 0 2 3]
AttributeEnd
Shape "trianglemesh" "point3 P" [-100 -100 10  100 -100 10  100 100 10  -100 100 10] "integer indices" [0 1 2 0 2 3]
)";
    const Scene scene = load_scene((dir / "moving.pbrt").string());
    FrameRenderer r(scene, options_for(scene, {"render.spp=1", "path.max_depth=1"}));
    r.request_aovs(true);
    Image img;
    for (int f = 0; f < 3; ++f) r.render_frame(card_camera(0), 10, img, nullptr);
    const Aovs& a = r.aovs();
    for (int y = 4; y < kCardHeight; y += 9) {
      // The card was 0.1 further left one frame ago: its history lies card_shift(0.1, 3) pixels left.
      CHECK(a.motion[a.index(kCardX, y)].x == doctest::Approx(-card_shift(0.1f, kCardZ)).epsilon(1e-3));
      CHECK(std::fabs(a.motion[a.index(kCardX, y)].y) < 1e-3f);
      CHECK(a.motion[a.index(kBackgroundX, y)].x == 0.0f);
    }
  }

  TEST_CASE("restir render --aov-dir writes one multi-channel EXR per frame") {
    const auto dir = fresh_temp_dir("aov-dir");
    const CommandResult r = run_restir("render " + own_scene("cornell-box.pbrt") + " --res 32x24 --spp 1 --frames 2 -q --aov-dir " +
                                       (dir / "aovs").string());
    REQUIRE_MESSAGE(r.status == 0, r.output);
    for (int f : {0, 1}) {
      const std::string path = (dir / "aovs" / ("aov_000" + std::to_string(f) + ".exr")).string();
      REQUIRE(std::filesystem::exists(path));
      bool frame = false;
      for (const auto& [k, v] : read_exr_metadata(path)) frame = frame || (k == "restir.frame" && v == std::to_string(f));
      CHECK(frame);
      Imf::InputFile file(path.c_str());
      for (const char* ch : {"Albedo.R", "Albedo.B", "N.X", "N.Z", "Z", "dZ", "Motion.X", "Motion.Y", "Emission.G", "SurfaceId"})
        CHECK_MESSAGE(file.header().channels().findChannel(ch) != nullptr, ch);
    }
  }
}

TEST_SUITE("aov") {
  TEST_CASE("emission is what the frame's own jittered camera samples saw: pt with no bounce renders exactly it") {
    // path.max_depth 0: the path tracer adds the primary hits' emission and nothing else, so its
    // frame is the emission AOV -- at the emitter's edges too, where the pixel centre's emission
    // is 0 or the whole light (the partial values below show that the edges are in the test).
    const Scene scene = load_scene(own_scene("cornell-box.pbrt"));
    for (const char* pattern : {"render.sample_pattern=random", "render.sample_pattern=halton"}) {
      CAPTURE(pattern);
      Options o = options_for(scene, {"integrator=pt", "film.width=48", "film.height=48", "render.spp=3", "path.max_depth=0", pattern});
      FrameRenderer r(scene, o);
      r.request_aovs(true);
      Image img;
      const CameraKey key = scene.camera.keys.front();
      int partial = 0;
      for (int f = 0; f < 2; ++f) {
        r.render_frame(key, 2, img, nullptr);
        const Aovs& a = r.aovs();
        float peak = 0;
        for (const Rgb& e : a.emission) peak = std::max(peak, e.x);
        REQUIRE(peak > 1.0f);
        for (size_t i = 0; i < img.pixels.size(); ++i) {
          CAPTURE(i);
          for (int c = 0; c < 3; ++c) CHECK(img.pixels[i][c] == doctest::Approx(a.emission[i][c]).epsilon(1e-6).scale(1e-6));
          partial += a.emission[i].x > 0.05f * peak && a.emission[i].x < 0.95f * peak;
        }
      }
      CHECK(partial > 0);
    }
  }
}
