#include <doctest/doctest.h>

#include <cmath>

#include "integrators/path/path_tracer.h"
#include "frame/render.h"
#include "backends/cpu/accel.h"
#include "scene/lights.h"
#include "scene/camera.h"
#include "test_helpers.h"

using namespace rl;
using namespace rl::test;

TEST_SUITE("path_tracer") {
  TEST_CASE("furnace: the closed cube with L=1 walls of albedo 0.5 renders 2 at depth 65") {
    Scene scene = load_scene(shared_scene("furnace.pbrt"));
    Options o = options_for(scene, {"film.width=32", "film.height=32", "render.spp=16"});
    CHECK(o.path.max_depth == 65);  // from the scene's Integrator directive
    RenderResult r = render(scene, o);
    for (int c = 0; c < 3; ++c) CHECK(mean_channel(r.last, c) == doctest::Approx(2.0).epsilon(0.01).scale(1e-9));
  }

  TEST_CASE("furnace: small depths give the geometric series sum_{i<=d} 0.5^i exactly in expectation") {
    Scene scene = load_scene(shared_scene("furnace.pbrt"));
    for (int depth : {0, 1, 2, 3, 5}) {
      for (const char* nee : {"path.nee=true", "path.nee=false"}) {
        Options o = options_for(scene, {"film.width=32", "film.height=32", "render.spp=32", nee,
                                        "path.russian_roulette=false"});
        o.path.max_depth = depth;
        RenderResult r = render(scene, o);
        const double expected = 2.0 - std::pow(0.5, depth);
        CAPTURE(depth);
        CAPTURE(nee);
        CHECK(mean_channel(r.last, 1) == doctest::Approx(expected).epsilon(0.004).scale(1e-9));
      }
    }
  }

  TEST_CASE("cosine sampling instead of BSDF sampling (thesis fig. 4.7 toggle) converges to the same furnace value") {
    Scene scene = load_scene(shared_scene("furnace.pbrt"));
    Options o = options_for(scene, {"film.width=32", "film.height=32", "render.spp=32", "path.bsdf_sampling=false",
                                    "path.max_depth=3", "path.russian_roulette=false"});
    CHECK(mean_channel(render(scene, o).last, 0) == doctest::Approx(1.875).epsilon(0.004).scale(1e-9));
  }

  // Issue 9: the wavefront path tracer (batched ray queries, bounce by bounce over a buffer of
  // path states, waves of 65536 paths) computes exactly what the one-path-at-a-time
  // path_radiance does, path by path; also across a wave boundary and with Russian roulette.
  TEST_CASE("the wavefront path tracer's image equals path_radiance's, pixel by pixel") {
    for (const char* rel : {"cornell-box/scene-v4.pbrt", "veach-mis/scene-v4.pbrt"}) {
      CAPTURE(rel);
      Scene scene = load_scene(shared_scene(rel));
      Options o = options_for(scene, {"film.width=96", "film.height=80", "render.spp=9", "path.max_depth=6",
                                      "path.russian_roulette=true", "path.rr_min_depth=1"});  // 69120 paths: two waves
      RenderResult r = render(scene, o);
      Accel accel(scene);
      Lights lights(scene, o.render.light_selection);
      RenderContext ctx{scene, accel, lights, o};
      PerspectiveCamera cam(scene.camera.at_frame(0, 1), o.film.width, o.film.height);
      size_t differ = 0;
      for (int y = 0; y < o.film.height; ++y)
        for (int x = 0; x < o.film.width; ++x) {
          const uint32_t pixel = uint32_t(y * o.film.width + x);
          Rgb sum(0);
          for (int s = 0; s < o.render.spp; ++s) {
            Pcg32 rng = make_rng(pixel, 0, RngPass::path, o.render.seed, uint32_t(s));
            sum += path_radiance(ctx, o.path, camera_ray(camera_sampling(ctx.options), cam, x, y, 0, s), rng);
          }
          const Rgb expected = sum / float(o.render.spp), got = r.last.at(x, y);
          differ += (expected.x != got.x || expected.y != got.y || expected.z != got.z) ? 1 : 0;
        }
      CHECK(differ == 0);
      CHECK(mean_channel(r.last, 1) > 0.01);
    }
  }

  TEST_CASE("the image does not depend on the thread count") {
    Scene scene = load_scene(shared_scene("cornell-box/scene-v4.pbrt"));
    Options o = options_for(scene, {"film.width=48", "film.height=48", "render.spp=2", "render.threads=1"});
    RenderResult one = render(scene, o);
    o.render.threads = 2;
    RenderResult two = render(scene, o);
    REQUIRE(one.last.size() == two.last.size());
    bool same = true;
    for (size_t i = 0; i < one.last.size(); ++i) same = same && one.last.pixels[i] == two.last.pixels[i];
    CHECK(same);
    o.render.seed = 7;
    RenderResult other = render(scene, o);
    bool differs = false;
    for (size_t i = 0; i < one.last.size(); ++i) differs = differs || !(one.last.pixels[i] == other.last.pixels[i]);
    CHECK(differs);  // the seed matters
  }

  TEST_CASE("Cornell box and Veach MIS render without NaN/Inf and with plausible brightness") {
    for (const char* s : {"cornell-box/scene-v4.pbrt", "veach-mis/scene-v4.pbrt"}) {
      Scene scene = load_scene(shared_scene(s));
      Options o = options_for(scene, {"film.width=64", "film.height=36", "render.spp=4"});
      RenderResult r = render(scene, o);
      int bad = 0;
      double sum = 0;
      for (const Rgb& p : r.last.pixels) {
        bad += is_finite(p) && p.x >= 0 && p.y >= 0 && p.z >= 0 ? 0 : 1;
        sum += luminance(p);
      }
      CAPTURE(s);
      CHECK(bad == 0);
      CHECK(sum / double(r.last.size()) > 0.01);
    }
  }

  TEST_CASE("camera: project() inverts generate_ray() and the fov spans the shorter axis") {
    CameraKey key;
    REQUIRE(look_at({1, 2, 3}, {0, 0, 0}, {0, 1, 0}, key.camera_from_world));
    key.fov_degrees = 40;
    PerspectiveCamera cam(key, 64, 32);
    for (Vec2 px : {Vec2{0.5f, 0.5f}, Vec2{10.25f, 20.75f}, Vec2{63.5f, 31.5f}}) {
      Ray r = cam.generate_ray(px);
      Vec2 back;
      REQUIRE(cam.project(r.o + r.d * 5.0f, back));
      CHECK(back.x == doctest::Approx(px.x).epsilon(1e-3).scale(1e-9));
      CHECK(back.y == doctest::Approx(px.y).epsilon(1e-3).scale(1e-9));
    }
    // Top and bottom edge rays are 40 degrees apart (height is the shorter axis).
    Ray top = cam.generate_ray({32, 0}), bottom = cam.generate_ray({32, 32});
    CHECK(std::acos(dot(top.d, bottom.d)) * 180 / kPi == doctest::Approx(40).epsilon(1e-3).scale(1e-9));
  }
}

TEST_SUITE("slow") {
  TEST_CASE("Cornell box: NEE+MIS, BSDF-only and cosine-sampled paths converge to the same image") {
    Scene scene = load_scene(shared_scene("cornell-box/scene-v4.pbrt"));
    auto run = [&](std::initializer_list<const char*> sets, int spp) {
      Options o = options_for(scene, {"film.width=16", "film.height=16", "path.max_depth=4"});
      o.render.spp = spp;
      for (const char* s : sets) set_option_assignment(o, s);
      return render(scene, o).last;
    };
    Image mis = run({"path.mis=power"}, 256), bal = run({"path.mis=balance"}, 256);
    Image bsdf_only = run({"path.nee=false"}, 2048), cosine = run({"path.bsdf_sampling=false"}, 256);
    for (int c = 0; c < 3; ++c) {
      double ref = mean_channel(mis, c);
      CHECK(mean_channel(bal, c) == doctest::Approx(ref).epsilon(0.02).scale(1e-9));
      CHECK(mean_channel(bsdf_only, c) == doctest::Approx(ref).epsilon(0.03).scale(1e-9));
      CHECK(mean_channel(cosine, c) == doctest::Approx(ref).epsilon(0.02).scale(1e-9));
    }
  }
}
