// Keyframed animation of shapes and lights (issue 11): the file format, interpolation (linear
// translation, slerp rotation, step), animate_scene and the BVH refit that follows it.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "integrators/render.h"
#include "scene/accel.h"
#include "scene/animation.h"
#include "scene/loader.h"
#include "scene/scene.h"

using namespace rl;
namespace fs = std::filesystem;

namespace {
fs::path temp_dir(const std::string& name) {
  fs::path d = fs::temp_directory_path() / ("restir-anim-" + name + "-" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}
void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }
bool near(Vec3 a, Vec3 b, float eps = 1e-4f) { return length(a - b) < eps; }
}  // namespace

TEST_SUITE("animation") {
  TEST_CASE("keys: linear translation, slerp rotation about the pivot, intensity; held before and after") {
    fs::path d = temp_dir("keys");
    write(d / "a.json", R"({"pivot": [1, 0, 0], "keys": [
        {"frame": 2, "translate": [0, 0, 0], "rotate": [0, 0, 1, 0], "intensity": 1},
        {"frame": 6, "translate": [4, 0, 0], "rotate": [90, 0, 1, 0], "intensity": 0}]})");
    const Animation a = load_animation((d / "a.json").string());
    // Before the first key and at it: the rest pose.
    CHECK(near(a.transform(0).apply_point({2, 0, 0}), {2, 0, 0}));
    CHECK(near(a.transform(2).apply_point({2, 0, 0}), {2, 0, 0}));
    // Half way: translated by 2, turned by 45 degrees about the y axis through the pivot (1, 0, 0).
    const float c = std::cos(kPi / 4);
    CHECK(near(a.transform(4).apply_point({2, 0, 0}), Vec3(1 + c, 0, -c) + Vec3(2, 0, 0)));
    CHECK(a.intensity(4) == doctest::Approx(0.5));
    // A quarter: 22.5 degrees (slerp moves at constant angular speed).
    const Vec3 q = a.transform(3).apply_point({2, 0, 0}) - Vec3(1, 0, 0) - Vec3(1, 0, 0);
    CHECK(std::atan2(-q.z, q.x) == doctest::Approx(kPi / 8).epsilon(1e-4));
    // After the last key: held.
    CHECK(near(a.transform(100).apply_point({2, 0, 0}), Vec3(1, 0, -1) + Vec3(4, 0, 0)));
    CHECK(a.intensity(100) == 0);
    // The rotation part stays orthonormal.
    const Mat4 m = a.transform(5);
    for (int i = 0; i < 3; ++i) CHECK(length(m.apply_vector(Vec3(i == 0, i == 1, i == 2))) == doctest::Approx(1).epsilon(1e-5));
    fs::remove_all(d);
  }

  TEST_CASE("step interpolation holds each key until the next: a switch") {
    fs::path d = temp_dir("step");
    write(d / "s.json", R"({"interpolation": "step", "keys": [{"frame": 0, "intensity": 1}, {"frame": 4, "intensity": 0},
        {"frame": 8, "intensity": 1}]})");
    const Animation a = load_animation((d / "s.json").string());
    CHECK(a.intensity(3) == 1);
    CHECK(a.intensity(4) == 0);
    CHECK(a.intensity(7) == 0);
    CHECK(a.intensity(8) == 1);
    fs::remove_all(d);
  }

  TEST_CASE("a scene's animated shapes and lights move with animate_scene; the BVH follows") {
    fs::path d = temp_dir("scene");
    write(d / "move.json", R"({"keys": [{"frame": 0}, {"frame": 4, "translate": [0, 10, 0]}]})");
    write(d / "dim.json", R"({"keys": [{"frame": 0, "intensity": 1}, {"frame": 4, "intensity": 0.25}]})");
    write(d / "s.pbrt",
          "Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\nCamera \"perspective\"\nWorldBegin\n"
          "Shape \"trianglemesh\" \"point3 P\" [-1 -1 5  1 -1 5  1 1 5] \"integer indices\" [0 1 2]\n"
          "AttributeBegin\n  Attribute \"shape\" \"string animation\" \"move.json\"\n"
          "  AreaLightSource \"diffuse\" \"rgb L\" [2 2 2]\n"
          "  Shape \"trianglemesh\" \"point3 P\" [-1 -1 8  1 -1 8  1 1 8] \"integer indices\" [0 1 2]\n"
          "  Shape \"sphere\" \"float radius\" 0.5\n"
          "AttributeEnd\n"
          "AttributeBegin\n  Attribute \"light\" \"string animation\" \"dim.json\"\n"
          "  LightSource \"point\" \"rgb I\" [4 4 4] \"point3 from\" [0 3 0]\nAttributeEnd\n"
          "LightSource \"point\" \"rgb I\" [1 1 1] \"point3 from\" [0 -3 0]\n");
    const Scene rest = load_scene((d / "s.pbrt").string());
    REQUIRE(rest.animations.size() == 2);
    CHECK(scene_animated(rest));
    CHECK(rest.meshes[0].animation == -1);
    CHECK(rest.meshes[1].animation == 0);
    CHECK(rest.spheres[0].animation == 0);
    CHECK(rest.point_lights[0].animation == 1);
    CHECK(rest.point_lights[1].animation == -1);
    CHECK(std::find(rest.input_files.begin(), rest.input_files.end(), (d / "move.json").string()) != rest.input_files.end());

    Scene s;
    animate_scene(rest, 0, s);
    Accel accel(s);
    const Ray ray{{0.5f, -0.5f, 0}, {0, 0, 1}};
    auto hit_z = [&](const Ray& r) {
      Hit h;
      return accel.intersect(r, h) ? r.o.z + h.t * r.d.z : -1.0f;
    };
    Ray through_moving{{0.5f, -0.5f, 6}, {0, 0, 1}};  // past the static triangle, toward the moving one
    CHECK(hit_z(through_moving) == doctest::Approx(8));
    animate_scene(rest, 2, s);  // half way: 5 up
    accel.update();
    CHECK(hit_z(through_moving) < 0);  // it left
    Ray raised = through_moving;
    raised.o.y += 5;
    CHECK(hit_z(raised) == doctest::Approx(8));
    CHECK(hit_z(ray) == doctest::Approx(5));  // the static one stays
    CHECK(near(s.spheres[0].center, {0, 5, 0}));
    CHECK(s.meshes[1].emission->radiance.x == doctest::Approx(2));  // no intensity keys: unchanged
    CHECK(s.point_lights[0].intensity.x == doctest::Approx(4 * 0.625));
    CHECK(s.point_lights[1].intensity.x == doctest::Approx(1));
    // Frame 0 again: back to the rest pose, exactly.
    animate_scene(rest, 0, s);
    CHECK(s.meshes[1].positions == rest.meshes[1].positions);
    fs::remove_all(d);
  }
}

namespace {
// Per-frame images of a 32x32 sequence of `rest`, averaged over `runs` seeds.
std::vector<Image> mean_frames(const Scene& rest, std::initializer_list<const char*> sets, int frames, int runs) {
  std::vector<Image> mean(size_t(frames), Image(32, 32));
  for (int k = 0; k < runs; ++k) {
    Options o;
    apply_scene_hints(o, rest.hints);
    o.film.width = o.film.height = 32;
    for (const char* a : sets) set_option_assignment(o, a);
    o.render.frames = frames;
    o.render.seed = uint64_t(1000 + k);
    RenderHooks hooks;
    hooks.on_frame = [&](int f, const Image& img, double) {
      for (size_t i = 0; i < img.size(); ++i) mean[size_t(f)].pixels[i] += img.pixels[i] / float(runs);
    };
    render(rest, o, hooks);
  }
  return mean;
}
// Mean luminance of each 8x8 block.
std::vector<double> blocks(const Image& img) {
  std::vector<double> b(16, 0);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) b[size_t((y / 8) * 4 + x / 8)] += luminance(img.at(x, y)) / 64;
  return b;
}
}  // namespace

TEST_SUITE("animation") {
  TEST_CASE("experiment: restir-di blocks in the dynamic room vs frozen pt references") {
    const Scene rest = load_scene(std::string(RESTIR_SOURCE_DIR) + "/scenes/dynamic-room.pbrt");
    const int frames = 14;
    auto di = mean_frames(rest, {"integrator=restir-di"}, frames, 16);
    std::string msg;
    for (int f : {3, 7, 8, 9, 10, 13}) {
      const Scene frozen = scene_at_frame(rest, f);
      Options o;
      apply_scene_hints(o, rest.hints);
      o.film.width = o.film.height = 32;
      o.render.spp = 1024;
      o.path.max_depth = 1;
      const Image ref = render(frozen, o).last;
      auto a = blocks(di[size_t(f)]), r = blocks(ref);
      double worst = 0;
      for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::fabs(a[i] / r[i] - 1));
      msg += fmt::format("f{}: worst block {:+.1f}%  ", f, 100 * worst);
      for (size_t i = 0; i < a.size(); ++i) msg += fmt::format("{:+.0f} ", 100 * (a[i] / r[i] - 1));
      msg += "\n";
    }
    MESSAGE(msg);
  }
}

namespace {
// Mean luminance of each frame of a sequence of the dynamic room at 32x32.
std::vector<double> frame_means(const Scene& rest, std::initializer_list<const char*> sets, int frames, uint64_t seed) {
  Options o;
  apply_scene_hints(o, rest.hints);
  o.film.width = o.film.height = 32;
  for (const char* a : sets) set_option_assignment(o, a);
  o.render.frames = frames;
  o.render.seed = seed;
  std::vector<double> means;
  RenderHooks hooks;
  hooks.on_frame = [&](int, const Image& img, double) {
    double sum = 0;
    for (const Rgb& p : img.pixels) sum += luminance(p);
    means.push_back(sum / double(img.size()));
  };
  render(rest, o, hooks);
  return means;
}
}  // namespace

TEST_SUITE("animation") {
  TEST_CASE("experiment: restir-di frame means in the dynamic room vs per-frame pt") {
    const Scene rest = load_scene(std::string(RESTIR_SOURCE_DIR) + "/scenes/dynamic-room.pbrt");
    const int frames = 14;
    std::vector<double> pt(frames, 0), di(frames, 0);
    const int runs = 4;
    for (int k = 0; k < runs; ++k) {
      auto a = frame_means(rest, {"integrator=pt", "render.spp=16", "path.max_depth=1"}, frames, 11 + k);
      auto b = frame_means(rest, {"integrator=restir-di"}, frames, 11 + k);
      for (int f = 0; f < frames; ++f) pt[size_t(f)] += a[size_t(f)] / runs, di[size_t(f)] += b[size_t(f)] / runs;
    }
    std::string msg;
    for (int f = 0; f < frames; ++f) msg += fmt::format("f{} pt {:.4f} di {:.4f} ({:+.1f}%)\n", f, pt[size_t(f)], di[size_t(f)], 100 * (di[size_t(f)] / pt[size_t(f)] - 1));
    MESSAGE(msg);
  }
}
