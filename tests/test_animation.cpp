// Keyframed animation of shapes and lights (issue 11): the file format, interpolation (linear
// translation, slerp rotation, step), animate_scene and the BVH refit that follows it.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

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
