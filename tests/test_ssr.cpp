// Screen-space reflections (issue 12): exact where SSR is exact -- a flat mirror reflecting an
// on-screen, unoccluded diffuse object and the sky -- and visibly wrong where it cannot be: the
// same object above the top of the frame leaves its reflection out.
#include <doctest/doctest.h>

#include <fstream>

#include "integrators/render.h"
#include "scene/accel.h"
#include "scene/camera.h"
#include "scene/loader.h"
#include "test_helpers.h"

using namespace rl;
using namespace rl::test;

namespace {
// A mirror floor under a constant sky, a dark diffuse box standing on it (box_y = 0) or floating
// above the top of the frame (box_y = 4) with its mirror image still in view.
std::string mirror_scene(float box_y) {
  const std::string path = std::string(RESTIR_BINARY_DIR) + "/ssr-mirror-" + std::to_string(int(box_y)) + ".pbrt";
  const float y0 = box_y, y1 = box_y + 1.2f;
  std::ofstream f(path);
  f << "LookAt 0 2 -6  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 60\n"
       "Film \"rgb\" \"integer xresolution\" 96 \"integer yresolution\" 72\nWorldBegin\n"
       "LightSource \"infinite\" \"rgb L\" [1 1 1]\n"
       "Material \"conductor\" \"float roughness\" 0 \"rgb reflectance\" [0.9 0.9 0.9]\n"
       "Shape \"trianglemesh\" \"point3 P\" [-8 0 -8  8 0 -8  8 0 8  -8 0 8] \"integer indices\" [0 2 1 0 3 2]\n"
       "Material \"diffuse\" \"rgb reflectance\" [0.15 0.1 0.08]\n"
       "Shape \"trianglemesh\" \"point3 P\" [-0.8 "
    << y0 << " -0.3  0.8 " << y0 << " -0.3  0.8 " << y1 << " -0.3  -0.8 " << y1 << " -0.3  -0.8 " << y0 << " 0.5  0.8 " << y0
    << " 0.5  0.8 " << y1 << " 0.5  -0.8 " << y1 << " 0.5]\n"
       "  \"integer indices\" [0 1 2 0 2 3  4 6 5 4 7 6  0 4 5 0 5 1  3 2 6 3 6 7  0 3 7 0 7 4  1 5 6 1 6 2]\n";
  return path;
}

struct Region {
  double ssr = 0, pt = 0;  // mean over the region
  int pixels = 0;
};

// Means of the SSR and path-traced images over the pixels whose primary surface is the mirror
// (all of them, or only those whose reference is darker than `below`: the reflected box).
Region mirror_region(const std::string& path, float below) {
  Scene scene = load_scene(path);
  Options o = options_for(scene, {"render.spp=256", "render.sample_pattern=center", "path.max_depth=2"});
  RenderResult pt = render(scene, o);
  o.integrator = "ssr";
  RenderResult ssr = render(scene, o);
  Accel accel(scene);
  PerspectiveCamera cam(scene.camera.at_frame(0, 1), o.film.width, o.film.height);
  Region r;
  for (int y = 0; y < o.film.height; ++y)
    for (int x = 0; x < o.film.width; ++x) {
      Ray ray = cam.generate_ray({float(x) + 0.5f, float(y) + 0.5f});
      Hit hit;
      if (!accel.intersect(ray, hit)) continue;
      if (scene.materials[size_t(accel.interaction(ray, hit).material)].type != Material::Type::conductor) continue;  // the mirror
      if (luminance(pt.last.at(x, y)) >= below) continue;
      r.ssr += luminance(ssr.last.at(x, y));
      r.pt += luminance(pt.last.at(x, y));
      ++r.pixels;
    }
  r.ssr /= std::max(1, r.pixels);
  r.pt /= std::max(1, r.pixels);
  return r;
}
}  // namespace

TEST_SUITE("ssr") {
  TEST_CASE("on a flat mirror SSR equals the path tracer (depth 2): the sky and an on-screen box") {
    const std::string path = mirror_scene(0);
    const Region all = mirror_region(path, 1e9f), box = mirror_region(path, 0.5f);
    const std::string what = "mirror: ssr " + std::to_string(all.ssr) + " pt " + std::to_string(all.pt) + " (" +
                             std::to_string(all.pixels) + " px); box reflection: ssr " + std::to_string(box.ssr) + " pt " +
                             std::to_string(box.pt) + " (" + std::to_string(box.pixels) + " px)";
    MESSAGE(what);
    CHECK(all.pixels > 2000);
    CHECK(box.pixels > 100);
    CHECK(std::fabs(all.ssr / all.pt - 1) < 0.01);
    CHECK(std::fabs(box.ssr / box.pt - 1) < 0.05);
  }

  TEST_CASE("an object above the frame: its reflection is missing from SSR (the sky instead)") {
    const std::string path = mirror_scene(4);
    const Region box = mirror_region(path, 0.5f);
    const std::string what = "off-screen box's reflection: ssr " + std::to_string(box.ssr) + " pt " + std::to_string(box.pt) +
                             " (" + std::to_string(box.pixels) + " px)";
    MESSAGE(what);
    CHECK(box.pixels > 50);
    CHECK(box.ssr > 0.8);  // the mirrored sky: 0.9
    CHECK(box.pt < 0.3);   // the mirrored dark box
  }
}
