// surface_at (scene_view.h): a surface point rebuilt from what identifies it -- geometry, primitive,
// barycentrics, and for a sphere the point -- must be the hit's own, bit for bit: ReSTIR PT's
// reservoir keeps only that of its reconnection vertex x_k (pt_path.h), and a shift that rebuilt a
// different normal or reflectance would evaluate another path than the one the walk sampled.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "backends/cpu/accel.h"
#include "random_rays.h"
#include "scene/loader.h"
#include "scene/scene_view.h"
#include "test_helpers.h"

using namespace rl;
using namespace rl::test;

namespace {

struct Rebuilt {
  int hits = 0, spheres = 0, textured = 0, shading_normals = 0, differ = 0;
};

bool same_bits(const SurfaceInteraction& a, const SurfaceInteraction& b) {
  return a.p == b.p && a.ng == b.ng && a.ns == b.ns && a.uv.x == b.uv.x && a.uv.y == b.uv.y && a.material == b.material &&
         a.is_sphere == b.is_sphere && a.geom == b.geom && a.prim == b.prim;
}

// Random rays through the scene: each closest hit's surface_interaction against surface_at of its
// record, and the material reflectance each gives (the texture lookup at the rebuilt uv).
Rebuilt rebuild(const std::string& path, size_t rays) {
  const Scene scene = load_scene(path);
  Accel accel(scene);
  const SceneView& sv = accel.scene_view();
  Rebuilt r;
  for (const Ray& ray : random_rays(scene, rays, 7)) {
    Hit hit;
    if (!accel.intersect(ray, hit)) continue;
    const SurfaceInteraction si = surface_interaction(sv, ray, hit);
    SurfaceInteraction again;
    ++r.hits;
    r.spheres += si.is_sphere;
    const MaterialParams& m = sv.materials[si.material];
    r.textured += m.reflectance_texture >= 0;
    r.shading_normals += !si.is_sphere && sv.meshes[si.geom].normals != nullptr;
    if (!surface_at(sv, si.geom, si.prim, si.barycentrics, si.p, again) || !same_bits(si, again) ||
        !(material_reflectance(sv, m, si.uv) == material_reflectance(sv, sv.materials[again.material], again.uv)))
      ++r.differ;
  }
  return r;
}

}  // namespace

// A checkerboard-textured quad with bent shading normals and uvs, and a textured sphere in front of
// it (none of the shipped scenes has a texture).
std::string textured_scene() {
  const std::filesystem::path path = fresh_temp_dir("surface_at") / "textured.pbrt";
  std::ofstream(path) << "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\nWorldBegin\n"
                         "Texture \"checks\" \"spectrum\" \"checkerboard\" \"float uscale\" 8 \"float vscale\" 8 "
                         "\"rgb tex1\" [0.9 0.1 0.1] \"rgb tex2\" [0.1 0.1 0.9]\n"
                         "Material \"diffuse\" \"texture reflectance\" \"checks\"\n"
                         "Shape \"trianglemesh\" \"point3 P\" [-2 -2 0  2 -2 0  2 2 0  -2 2 0] \"normal N\" [0 0 1  0.3 0 1  0 0.3 1  0 0 1] "
                         "\"point2 uv\" [0 0  1 0  1 1  0 1] \"integer indices\" [0 1 2  0 2 3]\n"
                         "AttributeBegin Translate 0 0 1 Shape \"sphere\" \"float radius\" 0.7 AttributeEnd\n";
  return path.string();
}

TEST_SUITE("scene") {
  TEST_CASE("surface_at rebuilds a hit's surface bit for bit from its record: triangles, shading normals, textures, spheres") {
    // Triangles with shading normals (the Cornell box, the teapots), spheres (many-lights' and
    // env-object's), flipped and plain normals, and a textured quad and sphere.
    Rebuilt total;
    for (const std::string& path : {shared_scene("cornell-box/scene-v4.pbrt"), own_scene("teapot.pbrt"), own_scene("teapot-table.pbrt"),
                                    own_scene("many-lights.pbrt"), own_scene("env-object.pbrt"), textured_scene()}) {
      CAPTURE(path);
      const Rebuilt r = rebuild(path, 20000);
      MESSAGE(path << ": " << r.hits << " hits, " << r.spheres << " on spheres, " << r.textured << " textured, " << r.shading_normals
                   << " with shading normals");
      CHECK(r.hits > 1000);
      CHECK(r.differ == 0);
      total.spheres += r.spheres, total.textured += r.textured, total.shading_normals += r.shading_normals;
    }
    // The check covered each kind of surface.
    CHECK(total.spheres > 100);
    CHECK(total.textured > 100);
    CHECK(total.shading_normals > 100);
  }

  TEST_CASE("surface_at: a degenerate triangle, whose normal the hit took from the ray, cannot be rebuilt") {
    Scene scene;
    TriangleMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}};  // collinear, then a proper one
    m.indices = {0, 1, 2, 3, 4, 5};
    scene.meshes.push_back(m);
    scene.materials.push_back(Material{});
    const SceneViewData data(scene);
    const SceneView sv = data.view();
    SurfaceInteraction si;
    CHECK_FALSE(surface_at(sv, 0, 0, Vec2{0.25f, 0.25f}, Vec3(0), si));
    REQUIRE(surface_at(sv, 0, 1, Vec2{0.25f, 0.25f}, Vec3(0), si));
    CHECK(si.ng == triangle_surface(sv, 0, 1, Vec2{0.25f, 0.25f}, Vec3(1, 0, 0)).ng);
    CHECK(std::fabs(std::fabs(si.ng.z) - 1.0f) < 1e-6f);
  }
}
