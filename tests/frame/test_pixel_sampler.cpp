#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <unistd.h>

#include "integrators/path/path_pixel.h"
#include "frame/pixel_sampler.h"
#include "scene/camera.h"

using namespace rl;

TEST_SUITE("pixel_sampler") {
  TEST_CASE("stratified: every stratum of a frame gets exactly one sample") {
    for (int spp : {1, 4, 9, 16, 6}) {
      Pcg32 rng(3);
      int nx = int(std::ceil(std::sqrt(float(spp)))), ny = (spp + nx - 1) / nx;
      std::set<int> cells;
      for (int s = 0; s < spp; ++s) {
        Vec2 u = pattern_sample(SamplePattern::stratified, uint64_t(s), spp, 0, rng);
        REQUIRE(u.x >= 0);
        REQUIRE(u.x < 1);
        REQUIRE(u.y >= 0);
        REQUIRE(u.y < 1);
        cells.insert(int(u.y * float(ny)) * nx + int(u.x * float(nx)));
      }
      CHECK(int(cells.size()) == spp);
    }
  }

  TEST_CASE("patterns anti-alias over frames: at a few samples per frame the positions cycle, not repeat") {
    Pcg32 rng(5);
    // stratified at 1, 2, 4, 8 spp per frame: 16 / spp frames put one sample in each cell of a 4x4
    // grid, and each frame's samples are spread (no two in one cell of the 2x2 grid when spp <= 4).
    for (int spp : {1, 2, 4, 8}) {
      std::set<int> cells;
      for (int f = 0; f < 16 / spp; ++f) {
        std::set<int> quadrants;
        for (int s = 0; s < spp; ++s) {
          const Vec2 u = pattern_sample(SamplePattern::stratified, uint64_t(f * spp + s), spp, 0, rng);
          REQUIRE((u.x >= 0 && u.x < 1 && u.y >= 0 && u.y < 1));
          cells.insert(int(u.y * 4) * 4 + int(u.x * 4));
          quadrants.insert(int(u.y * 2) * 2 + int(u.x * 2));
        }
        if (spp <= 4) CHECK(int(quadrants.size()) == spp);
      }
      CHECK(cells.size() == 16);
    }
    // msaa at 1 spp per frame: the 8 Direct3D 8x positions over 8 frames, then again.
    std::set<std::pair<float, float>> seen;
    for (uint64_t f = 0; f < 8; ++f) {
      const Vec2 p = pattern_sample(SamplePattern::msaa, f, 1, 0, rng);
      CHECK(p.x == msaa_position(8, int(f)).x);
      CHECK(p.y == msaa_position(8, int(f)).y);
      seen.insert({p.x, p.y});
    }
    CHECK(seen.size() == 8);
    CHECK(pattern_sample(SamplePattern::msaa, 8, 1, 0, rng).x == msaa_position(8, 0).x);
    // 16 spp per frame: the 16x pattern every frame.
    for (int i = 0; i < 16; ++i) CHECK(pattern_sample(SamplePattern::msaa, uint64_t(16 + i), 16, 0, rng).x == msaa_position(16, i).x);
  }

  TEST_CASE("halton: low discrepancy — each of the 4x4 cells gets one of the first 16 points (base 2 x 3 strata)") {
    Pcg32 rng(1);
    // Halton (2,3) without rotation: the first 2^k points stratify x into 2^k intervals.
    std::set<int> xs;
    for (uint64_t i = 0; i < 16; ++i) xs.insert(int(pattern_sample(SamplePattern::halton, i, 16, 0, rng).x * 16));
    CHECK(xs.size() == 16);
    // With a per-pixel rotation points stay in [0,1).
    for (uint64_t i = 0; i < 1000; ++i) {
      Vec2 u = pattern_sample(SamplePattern::halton, i, 4, 0x123456789abcdefULL, rng);
      CHECK((u.x >= 0 && u.x < 1 && u.y >= 0 && u.y < 1));
    }
  }

  TEST_CASE("msaa: the Direct3D standard patterns are centred and distinct") {
    for (int n : {1, 2, 4, 8, 16}) {
      CHECK(msaa_pattern_size(n) == n);
      Vec2 sum{0, 0};
      std::set<std::pair<float, float>> distinct;
      for (int i = 0; i < n; ++i) {
        Vec2 p = msaa_position(n, i);
        CHECK((p.x >= 0 && p.x < 1 && p.y >= 0 && p.y < 1));
        sum = sum + (p - Vec2{0.5f, 0.5f});
        distinct.insert({p.x, p.y});
      }
      CHECK(int(distinct.size()) == n);
      CHECK(std::fabs(sum.x / float(n)) < 0.07f);
      CHECK(std::fabs(sum.y / float(n)) < 0.07f);
    }
    CHECK(msaa_pattern_size(3) == 4);
    CHECK(msaa_pattern_size(64) == 16);
    CHECK(msaa_position(4, 0).x == doctest::Approx(0.5 - 2.0 / 16));
  }

  TEST_CASE("filters: box covers [-r, r], tent has its mean at 0 and mass near the centre") {
    Pcg32 rng(9);
    double mean = 0, inner = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
      Vec2 o = filter_offset(PixelFilter::triangle, 1.0f, rng.next_2d(), rng);
      REQUIRE(std::fabs(o.x) <= 1.0f);
      mean += o.x;
      inner += std::fabs(o.x) < 0.5f ? 1 : 0;
      Vec2 b = filter_offset(PixelFilter::box, 0.5f, rng.next_2d(), rng);
      REQUIRE(std::fabs(b.x) <= 0.5f);
    }
    CHECK(std::fabs(mean / n) < 0.02);
    CHECK(inner / n == doctest::Approx(0.75).epsilon(0.03).scale(1e-9));  // tent: P(|x| < r/2) = 3/4
  }
}

TEST_SUITE("camera") {
  TEST_CASE("generate_ray: the precomputed raster map is pbrt's raster -> screen -> camera -> world") {
    // The camera folds the map into origin + x dx + y dy (issue 9); the direction must be the
    // one pbrt's formula gives, landscape and portrait, and with a mirrored (Scale -1 1 1) camera.
    for (bool mirrored : {false, true})
      for (auto [w, h] : {std::pair{64, 32}, std::pair{30, 90}}) {
        CameraKey key;
        REQUIRE(look_at({1, 2, 3}, {0.2f, -0.1f, 0}, {0, 1, 0}, key.camera_from_world));
        if (mirrored)
          for (int c = 0; c < 4; ++c) key.camera_from_world.m[0][c] = -key.camera_from_world.m[0][c];
        key.fov_degrees = 55;
        const PerspectiveCamera cam(key, w, h);
        Mat4 world_from_camera;
        REQUIRE(key.camera_from_world.inverse(world_from_camera));
        const float t = std::tan(55.0f * 0.5f * kPi / 180), ratio = float(w) / float(h);
        const float sx = ratio > 1 ? ratio : 1, sy = ratio > 1 ? 1 : 1 / ratio;
        for (Vec2 px : {Vec2{0, 0}, Vec2{float(w), float(h)}, Vec2{0.5f, float(h) - 3.25f}, Vec2{float(w) * 0.5f, float(h) * 0.5f}}) {
          const Vec3 cam_dir{(px.x / float(w) * 2 - 1) * sx * t, (1 - px.y / float(h) * 2) * sy * t, 1};
          const Vec3 expect = normalize(world_from_camera.apply_vector(cam_dir));
          const Ray r = cam.generate_ray(px);
          CAPTURE(mirrored);
          CAPTURE(w);
          CAPTURE(px.x);
          CHECK(length(r.d - expect) < 1e-6f);
          CHECK(length(r.o - world_from_camera.apply_point(Vec3(0))) < 1e-5f);
        }
      }
  }

  TEST_CASE("camera_ray seeds the pixel's stream wherever the pattern or the filter draws from it") {
    // camera_ray skips seeding the stream (and the Halton pixel hash) where nothing reads it; the
    // rays must be those of the version that always seeds both, for every pattern and filter.
    CameraKey key;
    REQUIRE(look_at({0, 0, -3}, {0, 0, 0}, {0, 1, 0}, key.camera_from_world));
    key.fov_degrees = 45;
    const PerspectiveCamera cam(key, 17, 11);
    int differing_pixels = 0;
    for (SamplePattern pattern : {SamplePattern::center, SamplePattern::random, SamplePattern::stratified, SamplePattern::halton,
                                  SamplePattern::msaa})
      for (PixelFilter filter : {PixelFilter::box, PixelFilter::triangle, PixelFilter::gaussian})
        for (int spp : {1, 3, 4}) {
          const CameraSampling cs{7, spp, pattern, filter, 1.5f};
          for (int frame : {0, 5})
            for (int y = 0; y < 11; y += 2)
              for (int x = 0; x < 17; x += 3)
                for (int s = 0; s < spp; ++s) {
                  const uint32_t pixel = uint32_t(y * 17 + x);
                  Pcg32 rng = make_rng(pixel, uint32_t(frame), RngPass::camera, cs.seed, uint32_t(s));
                  const Vec2 u = pattern_sample(pattern, uint64_t(frame) * uint64_t(spp) + uint64_t(s), spp,
                                                mix64(hash_combine(cs.seed, pixel)), rng);
                  const Vec2 o = filter_offset(filter, cs.filter_radius, u, rng);
                  const Ray expect = cam.generate_ray({float(x) + 0.5f + o.x, float(y) + 0.5f + o.y});
                  const Ray got = camera_ray(cs, cam, x, y, frame, s);
                  CAPTURE(int(pattern));
                  CAPTURE(int(filter));
                  REQUIRE(got.d.x == expect.d.x);
                  REQUIRE(got.d.y == expect.d.y);
                  REQUIRE(got.d.z == expect.d.z);
                  differing_pixels += got.d.x != camera_ray(cs, cam, 0, 0, frame, s).d.x;
                }
        }
    CHECK(differing_pixels > 0);
  }

  TEST_CASE("camera path: keys are spread over the frames and interpolated") {
    namespace fs = std::filesystem;
    fs::path p = fs::temp_directory_path() / ("restir-cam-" + std::to_string(::getpid()) + ".json");
    std::ofstream(p) << R"({"keys": [{"eye": [0,0,0], "target": [0,0,1], "fov": 30},
                                      {"eye": [2,0,0], "target": [2,0,1], "fov": 50}]})";
    Camera cam;
    load_camera_path(p.string(), cam);
    REQUIRE(cam.keys.size() == 2);
    auto position = [&](int f, int n) { return PerspectiveCamera(cam.at_frame(f, n), 8, 8).position(); };
    CHECK(position(0, 5).x == doctest::Approx(0));
    CHECK(position(4, 5).x == doctest::Approx(2));
    CHECK(position(2, 5).x == doctest::Approx(1));
    CHECK(cam.at_frame(2, 5).fov_degrees == doctest::Approx(40));
    std::ofstream(p) << R"({"keys": [{"eye": [0,0,0], "target": [0,0,0]}]})";
    CHECK_THROWS(load_camera_path(p.string(), cam));
    std::ofstream(p) << R"({"frames": []})";
    CHECK_THROWS(load_camera_path(p.string(), cam));
    fs::remove(p);
  }
}
