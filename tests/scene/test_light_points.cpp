#include <doctest/doctest.h>

#include <cmath>

#include "core/rng.h"
#include "scene/lights.h"

using namespace rl;

TEST_SUITE("lights") {
  TEST_CASE("sample_point: density agrees with point_pdf and integrates each emitter's area (or 4pi)") {
    Scene scene;
    scene.materials.push_back(Material{});
    TriangleMesh quad;
    quad.positions = {{0, 0, 0}, {2, 0, 0}, {2, 3, 0}, {0, 3, 0}};
    quad.indices = {0, 1, 2, 0, 2, 3};
    quad.emission = AreaEmission{Rgb(1, 2, 3), false};
    scene.meshes.push_back(quad);
    Sphere sph;
    sph.center = {5, 0, 0};
    sph.radius = 0.5f;
    sph.emission = AreaEmission{Rgb(10), false};
    scene.spheres.push_back(sph);
    scene.point_lights.push_back({{0, 5, 0}, Rgb(4)});
    EnvironmentLight env;
    env.radiance = Rgb(0.5f);
    scene.environment = env;
    for (LightSelection sel : {LightSelection::power, LightSelection::uniform}) {
      Lights lights(scene, sel);
      REQUIRE(lights.emitter_count() == 5);
      Pcg32 rng(11);
      const int n = 400000;
      std::vector<double> sum(lights.emitter_count(), 0.0), sum2(lights.emitter_count(), 0.0);
      for (int i = 0; i < n; ++i) {
        EmitterPoint p;
        float us = rng.next_float();
        Vec2 u = rng.next_2d();
        if (!lights.sample_point(us, u, p)) continue;
        REQUIRE(p.pdf == doctest::Approx(lights.point_pdf(p.emitter, p.position)).epsilon(1e-4).scale(1e-9));
        // Each emitter's own measure: E[1/pdf over its samples] = area (triangles, spheres), 4pi (env), 1 (point).
        const double v = 1.0 / p.pdf;
        sum[p.emitter] += v;
        sum2[p.emitter] += v * v;
      }
      const double expected[5] = {3, 3, kPi, 1, 4 * kPi};  // two triangles of the 2x3 quad, sphere area 4 pi r^2 = pi
      for (size_t e = 0; e < 5; ++e) {
        const double mean = sum[e] / n, se = std::sqrt((sum2[e] / n - mean * mean) / n);
        CAPTURE(e);
        CHECK(std::fabs(mean - expected[e]) < 4 * se + 1e-6);
      }
    }
  }
}
