// Render-level analytic checks of the spot and distant lights: a diffuse plane (reflectance rho)
// seen from above through pixel centres, lit by one delta light, at depth 1. Light sampling is the
// only strategy and has one outcome per pixel, so the path tracer's estimate is the exact value
// rho / pi * E in every pixel (E the irradiance), and so is every unbiased resampling of it: ReSTIR
// DI's and PT's reservoirs can only hold that one light, with MIS weights that sum to 1 (GI's direct
// light is one light sample, its reservoirs hold the indirect part, 0 here).
#include <doctest/doctest.h>

#include <cmath>
#include <fstream>

#include "frame/render.h"
#include "scene/camera.h"
#include "scene/lights.h"
#include "test_helpers.h"

using namespace rl;
using namespace rl::test;

namespace {

constexpr float kRho = 0.5f;

// A 40 x 40 diffuse plane at y = 0 under a camera 3 above it looking down (fov 90), plus `light`.
Scene plane_scene(const std::string& name, const std::string& light) {
  const std::string path = (fresh_temp_dir(name) / "s.pbrt").string();
  std::ofstream(path) << "LookAt 0 3 0  0 0 0  0 0 1\nCamera \"perspective\" \"float fov\" 90\n"
                         "Film \"rgb\" \"integer xresolution\" 33 \"integer yresolution\" 33\nWorldBegin\n"
                      << light << "\nMaterial \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]\n"
                      << "Shape \"trianglemesh\" \"point3 P\" [-20 0 -20  20 0 -20  20 0 20  -20 0 20] "
                         "\"integer indices\" [0 1 2 0 2 3]\n";
  return load_scene(path);
}

// Each pixel's primary ray through its centre (box filter of radius 0, centre pattern).
// ReSTIR DI is direct light by definition and reads no path.* keys.
Options depth1_options(const Scene& scene, const std::string& integrator) {
  Options o = options_for(scene, {"render.spp=1", "render.frames=2", "render.sample_pattern=center", "film.filter=box",
                                  "film.filter_radius=0"});
  set_option(o, "integrator", integrator);
  if (integrator != "restir-di") {
    set_option(o, "path.max_depth", "1");
    set_option(o, "path.russian_roulette", "false");
  }
  return o;
}

// Where pixel (x, y)'s centre ray meets the plane y = 0.
Vec3 plane_point(const Scene& scene, int x, int y, int w, int h) {
  const PerspectiveCamera cam(scene.camera.at_frame(0, 1), w, h);
  const Ray r = cam.generate_ray({float(x) + 0.5f, float(y) + 0.5f});
  return r.o + r.d * (-r.o.y / r.d.y);
}

}  // namespace

TEST_SUITE("path_tracer") {
  TEST_CASE("a distant light at theta = 30 deg on a diffuse plane: every pixel is rho / pi L cos theta") {
    const float theta = 30 * kPi / 180, L = 2;
    const Scene scene = plane_scene("distant-plane", "LightSource \"distant\" \"point3 from\" [" + std::to_string(std::sin(theta)) +
                                                         " " + std::to_string(std::cos(theta)) + " 0] \"point3 to\" [0 0 0] \"rgb L\" [2 2 2]");
    const double expected = kRho / kPi * L * std::cos(theta);
    for (const std::string integrator : {"pt", "restir-di", "restir-gi", "restir-pt"}) {
      CAPTURE(integrator);
      const Image img = render(scene, depth1_options(scene, integrator)).last;
      double worst = 0;
      for (const Rgb& p : img.pixels) worst = std::max(worst, std::fabs(double(p.y) - expected));
      CHECK(worst <= 1e-4 * expected);
    }
  }

  TEST_CASE("a spot 2 above a diffuse plane: rho / pi I / h^2 below it, the smoothstep band, 0 outside the cone") {
    const float h = 2, I = 5, cone = 30, delta = 10;
    const Scene scene = plane_scene("spot-plane", "LightSource \"spot\" \"point3 from\" [0 2 0] \"point3 to\" [0 0 0] \"rgb I\" [5 5 5] "
                                                  "\"float coneangle\" 30 \"float conedeltaangle\" 10");
    const int w = 33, ht = 33;
    for (const std::string integrator : {"pt", "restir-di", "restir-gi", "restir-pt"}) {
      CAPTURE(integrator);
      const Image img = render(scene, depth1_options(scene, integrator)).last;
      CHECK(img.at(16, 16).y == doctest::Approx(kRho / kPi * I / (h * h)).epsilon(1e-4));  // straight below
      int dark = 0, band = 0, worst_x = -1, worst_y = -1;
      double worst = 0;
      for (int y = 0; y < ht; ++y)
        for (int x = 0; x < w; ++x) {
          const Vec3 p = plane_point(scene, x, y, w, ht);
          const float d2 = p.x * p.x + p.z * p.z + h * h, cos_t = h / std::sqrt(d2);
          const float f = spot_falloff(cos_t, std::cos(cone * kPi / 180), std::cos((cone - delta) * kPi / 180));
          const double expected = kRho / kPi * I * f * cos_t / d2, err = std::fabs(double(img.at(x, y).y) - expected);
          dark += f == 0 ? 1 : 0;
          band += f > 0 && f < 1 ? 1 : 0;
          if (f == 0) CHECK(img.at(x, y).y == 0.0f);
          if (err > worst) worst = err, worst_x = x, worst_y = y;
        }
      CAPTURE(worst_x);
      CAPTURE(worst_y);
      CHECK(dark > 100);  // the image reaches past the cone (radius 3 against 2 tan 30 = 1.15)
      CHECK(band > 20);   // and shows the band
      CHECK(worst <= 1e-4 * kRho / kPi * I / (h * h));
    }
  }
}
