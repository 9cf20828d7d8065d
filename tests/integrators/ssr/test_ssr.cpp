// Screen-space reflections (issue 12): exact where SSR is exact -- a flat mirror reflecting an
// on-screen, unoccluded diffuse object and the sky -- and visibly wrong where it cannot be: the
// same object above the top of the frame leaves its reflection out.
#include <doctest/doctest.h>

#include <cmath>
#include <fstream>

#include "frame/gbuffer.h"
#include "frame/render.h"
#include "integrators/ssr/ssr_march.h"
#include "scene/bsdf.h"
#include "scene/lights.h"
#include "scene/texture.h"
#include "backends/cpu/accel.h"
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

// Per-pixel mean and variance over K seeds of the last frame, restricted to the pixels whose
// primary surface has roughness in (lo, hi] (at the pixel centre).
struct SeedStats {
  double mean = 0, variance = 0;
  int pixels = 0;
};
SeedStats seed_stats(const std::string& path, std::initializer_list<const char*> sets, float lo, float hi, int seeds) {
  Scene scene = load_scene(path);
  Options o = options_for(scene, sets);
  std::vector<Image> images;
  for (int k = 0; k < seeds; ++k) {
    o.render.seed = uint64_t(101 + k);
    images.push_back(render(scene, o).last);
  }
  Accel accel(scene);
  Camera camera = scene.camera;  // the last frame's view (of the camera path, if any)
  if (!o.render.camera_path.empty()) load_camera_path(o.render.camera_path, camera);
  PerspectiveCamera cam(camera.at_frame(o.render.frames - 1, o.render.frames), o.film.width, o.film.height);
  SeedStats st;
  for (int y = 0; y < o.film.height; ++y)
    for (int x = 0; x < o.film.width; ++x) {
      Ray ray = cam.generate_ray({float(x) + 0.5f, float(y) + 0.5f});
      Hit hit;
      if (!accel.intersect(ray, hit)) continue;
      const SurfaceInteraction si = accel.interaction(ray, hit);
      const Material& m = scene.materials[size_t(si.material)];
      const float r = bsdf_roughness(make_bsdf(m, material_reflectance(scene, m, si.uv)));
      if (!(r > lo && r <= hi)) continue;
      double sum = 0, sum2 = 0;
      for (const Image& im : images) {
        const double v = luminance(im.at(x, y));
        sum += v;
        sum2 += v * v;
      }
      const double mean = sum / seeds;
      st.mean += mean;
      st.variance += (sum2 - seeds * mean * mean) / (seeds - 1);
      ++st.pixels;
    }
  st.mean /= std::max(1, st.pixels);
  st.variance /= std::max(1, st.pixels);
  return st;
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

  TEST_CASE("ssr's lit colour is the path tracer at depth 1, pixel for pixel (primary hits traced once)") {
    // With roughness_cutoff 0 no surface of the Cornell box reflects the screen: ssr shows its lit
    // colour everywhere, which continues the G-buffer's hits with path_radiance's random numbers.
    Scene scene = load_scene(shared_scene("cornell-box/scene-v4.pbrt"));
    Options o = options_for(scene, {"film.width=48", "film.height=48", "render.spp=2", "path.max_depth=1"});
    const Image pt = render(scene, o).last;
    o.integrator = "ssr";
    o.ssr.roughness_cutoff = 0;
    const Image ssr = render(scene, o).last;
    REQUIRE(pt.pixels.size() == ssr.pixels.size());
    int differ = 0;
    for (size_t i = 0; i < pt.pixels.size(); ++i)
      differ += !(pt.pixels[i].x == ssr.pixels[i].x && pt.pixels[i].y == ssr.pixels[i].y && pt.pixels[i].z == ssr.pixels[i].z);
    CHECK(differ == 0);
  }

  TEST_CASE("the Hi-Z march finds what the screen shows at least as often as the per-pixel march, in fewer steps") {
    // Ground truth from Embree: a ray whose first hit is visible on screen (the pixel it projects
    // to shows that very point) should land on that pixel; a ray that escapes the scene should
    // find nothing. (Rays whose first hit is hidden from the camera have no right answer on screen.)
    for (const char* name : {"mirror-floor.pbrt", "teapot-table.pbrt"}) {
      Scene scene = load_scene(own_scene(name));
      Options o = options_for(scene, {"film.width=160", "film.height=90"});
      Accel accel(scene);
      Lights lights(scene, o.render.light_selection);
      RenderContext ctx{scene, accel, lights, o};
      PerspectiveCamera cam(scene.camera.at_frame(0, 1), o.film.width, o.film.height);
      GBuffer g;
      build_gbuffer(ctx, cam, 0, 0, g);
      HiZPyramid pyramid;
      pyramid.build(cam, g);
      const HiZView hiz = pyramid.view();
      // The pyramid holds the nearest depth of each cell.
      const HiZLayout& layout = hiz.layout;
      for (int l = 1; l < layout.levels; ++l)
        for (int y = 0; y < layout.height[l - 1]; ++y)
          for (int x = 0; x < layout.width[l - 1]; ++x) REQUIRE(hiz.at(l, x / 2, y / 2) <= hiz.at(l - 1, x, y));
      REQUIRE(layout.width[layout.levels - 1] == 1);
      REQUIRE(layout.height[layout.levels - 1] == 1);
      const float extent = length(scene.bounds().diagonal());
      Pcg32 rng(7, 11);
      int judged = 0, right_linear = 0, right_hiz = 0, visible = 0;
      double steps_linear = 0, steps_hiz = 0;
      for (const GPacked& packed : g.pixels) {
        const GSurface sf = unpack_surface(packed, g.materials.data(), g.eye);
        if (!sf.valid || bsdf_roughness(sf.bsdf) > 0.3f) continue;
        for (int k = 0; k < 2; ++k) {
          BsdfSample bs;
          const float u_lobe = rng.next_float();
          if (!bsdf_sample(sf.bsdf, sf.frame().to_local(sf.wo), u_lobe, rng.next_2d(), bs)) continue;
          const Vec3 d = sf.frame().to_world(bs.wi);
          const Ray ray = spawn_ray(sf.p, sf.ng, d, accel.ray_epsilon());
          Hit truth;
          int tx = -1, ty = -1;
          if (accel.intersect(ray, truth)) {
            const Vec3 q = ray.o + d * truth.t;
            Vec2 r;
            if (!cam.project(q, r)) continue;
            tx = int(r.x);
            ty = int(r.y);
            const GSurface& shown = g.at(tx, ty);
            if (!shown.valid || length(shown.p - q) > 0.02f * shown.depth) continue;  // hidden: no right answer
            ++visible;
          }
          const MarchResult a = march_linear(cam, view_of(g), hiz, ray.o, d, extent, 1 << 16, 0.05f);
          const MarchResult h = march_hiz(cam, view_of(g), hiz, ray.o, d, extent, 1 << 16, 0.05f);
          auto right = [&](const MarchResult& m) {
            return tx < 0 ? !m.hit : m.hit && std::abs(m.x - tx) <= 1 && std::abs(m.y - ty) <= 1;
          };
          ++judged;
          right_linear += right(a);
          right_hiz += right(h);
          steps_linear += a.steps;
          steps_hiz += h.steps;
        }
      }
      const std::string what = std::string(name) + ": " + std::to_string(judged) + " rays judged (" + std::to_string(visible) +
                               " land on screen); right: linear " + std::to_string(double(right_linear) / judged) +
                               ", Hi-Z " + std::to_string(double(right_hiz) / judged) + "; steps per ray: linear " +
                               std::to_string(steps_linear / judged) + ", Hi-Z " + std::to_string(steps_hiz / judged);
      MESSAGE(what);
      CHECK(judged > 1000);
      CHECK(visible > judged / 10);
      CHECK(double(right_hiz) / judged >= 0.95);
      CHECK(right_hiz >= right_linear);
      CHECK(steps_hiz < steps_linear);
    }
  }

}

// Noise over seeds: statistical, labelled slow.
TEST_SUITE("slow_ssr") {
  TEST_CASE("the resolve lowers the noise of glossy reflections and leaves mirrors alone") {
    // Glossy pixels of the teapot table (roughness 0.02-0.3): the variance over seeds of one
    // frame, resolve with 4 neighbours vs the pixel's own ray; the means within a few percent.
    // (Primary rays through the pixel centres: the noise is the reflections' and the lit colour's.)
    const std::string table = own_scene("teapot-table.pbrt");
    const SeedStats own = seed_stats(table, {"integrator=ssr", "film.width=96", "film.height=54", "render.sample_pattern=center", "ssr.resolve_neighbors=0"}, 0.01f, 0.3f, 8);
    const SeedStats res = seed_stats(table, {"integrator=ssr", "film.width=96", "film.height=54", "render.sample_pattern=center"}, 0.01f, 0.3f, 8);
    const std::string what = "glossy pixels: " + std::to_string(own.pixels) + "; mean own " + std::to_string(own.mean) +
                             " resolved " + std::to_string(res.mean) + "; variance own " + std::to_string(own.variance) +
                             " resolved " + std::to_string(res.variance);
    MESSAGE(what);
    CHECK(own.pixels > 500);
    CHECK(res.variance < own.variance / 1.4);  // measured 1.6x (the lit colour the rays return stays noisy)
    CHECK(std::fabs(res.mean / own.mean - 1) < 0.05);
    // A mirror (delta lobe) reuses nothing: the images are equal.
    Scene scene = load_scene(mirror_scene(0));
    Options o = options_for(scene, {"integrator=ssr", "render.spp=1", "ssr.resolve_neighbors=0"});
    const Image a = render(scene, o).last;
    o.ssr.resolve_neighbors = 8;
    const Image b = render(scene, o).last;
    CHECK(a.pixels == b.pixels);
  }

  TEST_CASE("temporal accumulation under a fast dolly: the reflections' history does not lag") {
    // The camera moves 0.7 a frame toward the table (about 13 % of its distance). Reprojecting a
    // reflection with its surface drags what it showed a frame ago along (the mean of the glossy
    // pixels -4 %); with its virtual image (parallax-corrected) the mean stays. The history does
    // not lower the noise here: fetched at each pixel's noisy reflection depth it flickers (the
    // variance over seeds rises about 3x) -- temporal accumulation is for a slow camera.
    const std::string path = std::string(RESTIR_BINARY_DIR) + "/ssr-dolly.json";
    std::ofstream(path) << R"({"keys": [{"eye": [0, 1.5, -4.5], "target": [0, 0.45, 0.8], "up": [0, 1, 0], "fov": 38},
                                        {"eye": [0, 1.2, -1.7], "target": [0, 0.45, 0.8], "up": [0, 1, 0], "fov": 38}]})";
    const std::string table = own_scene("teapot-table.pbrt");
    const std::string cp = "render.camera_path=" + path;
    const SeedStats off = seed_stats(table, {"integrator=ssr", "film.width=96", "film.height=54", "render.frames=5", cp.c_str()}, 0.01f, 0.3f, 6);
    const SeedStats on = seed_stats(table, {"integrator=ssr", "film.width=96", "film.height=54", "render.frames=5", cp.c_str(),
                                            "ssr.temporal=true", "ssr.temporal_alpha=0.3"}, 0.01f, 0.3f, 6);
    const std::string what = "glossy pixels after a 5-frame dolly: variance without history " + std::to_string(off.variance) +
                             ", with " + std::to_string(on.variance) + " (" + std::to_string(on.pixels) + " px); means " + std::to_string(off.mean) + " / " + std::to_string(on.mean);
    MESSAGE(what);
    CHECK(on.pixels > 300);
    CHECK(std::fabs(on.mean / off.mean - 1) < 0.02);
  }

  TEST_CASE("temporal accumulation: a still camera's reflections converge over frames") {
    const std::string table = own_scene("teapot-table.pbrt");
    const SeedStats off = seed_stats(table, {"integrator=ssr", "film.width=96", "film.height=54", "render.frames=8"}, 0.01f, 0.3f, 6);
    const SeedStats on = seed_stats(table, {"integrator=ssr", "film.width=96", "film.height=54", "render.frames=8",
                                            "ssr.temporal=true", "ssr.temporal_alpha=0.2"}, 0.01f, 0.3f, 6);
    const std::string what = "glossy pixels, frame 8: variance without history " + std::to_string(off.variance) +
                             ", with " + std::to_string(on.variance) + "; means " + std::to_string(off.mean) + " / " +
                             std::to_string(on.mean);
    MESSAGE(what);
    CHECK(on.variance < off.variance / 2.5);
    CHECK(std::fabs(on.mean / off.mean - 1) < 0.05);
  }
}
