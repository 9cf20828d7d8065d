// Issue 16: the CUDA backend's BVH (built with Embree's SAH builder into our own layout) and its
// traversal (bvh_traverse.h, the code the GPU runs), proved on the CPU against Embree: the same
// closest hits and occlusion for random rays in real scenes, and the same path-traced image.
#include <doctest/doctest.h>

#include <cmath>

#include "backends/bvh.h"
#include "backends/bvh_queries.h"
#include "backends/bvh_traverse.h"
#include "backends/cuda/cuda_queries.h"
#include "frame/integrator.h"
#include "frame/render.h"
#include "backends/cpu/accel.h"
#include "scene/lights.h"
#include "query_agreement.h"
#include "random_rays.h"
#include "test_helpers.h"

using namespace rl;
using namespace rl::test;

namespace {

using Agreement = QueryAgreement;

// Compares BvhQueries with Embree (Accel) on the rays: the same hit or miss, the same primitive
// (or, at a shared edge, another one at the same distance), t within a relative 1e-4.
Agreement compare(const Scene& scene, const std::vector<Ray>& rays) {
  Accel accel(scene);
  BvhQueries bvh(scene);
  return compare_queries(accel, bvh, rays, [&](size_t, const Hit& a, const Hit& b, Agreement& g) {
    const bool t_close = std::fabs(a.t - b.t) <= 1e-4f * std::max(1.0f, a.t);
    if (!t_close) ++g.t_mismatch;
    else if (a.geom == b.geom && a.prim == b.prim && a.geom != bvh.bvh().sphere_geom &&
             (std::fabs(a.u - b.u) > 1e-3f || std::fabs(a.v - b.v) > 1e-3f))
      ++g.t_mismatch;  // same triangle, other barycentrics: as wrong as another distance
  });
}

}  // namespace

TEST_SUITE("bvh") {
  TEST_CASE("the BVH holds every primitive once, and every box holds its subtree") {
    Scene scene = load_scene(own_scene("teapot.pbrt"));
    const Bvh bvh = build_bvh(scene);
    REQUIRE(bvh.primitives.size() == scene.triangle_count() + scene.spheres.size());
    CHECK(bvh.depth <= kBvhMaxDepth);
    std::vector<int> seen(bvh.primitives.size(), 0);
    std::vector<size_t> offset(scene.meshes.size() + 1, 0);
    for (size_t m = 0; m < scene.meshes.size(); ++m) offset[m + 1] = offset[m] + scene.meshes[m].triangle_count();
    for (const BvhPrimitive& p : bvh.primitives) ++seen[offset[p.geom] + p.prim];
    CHECK(std::all_of(seen.begin(), seen.end(), [](int c) { return c == 1; }));
    // Each child box contains the primitives (leaf) or both boxes (inner) below it.
    size_t bad = 0;
    for (const BvhNode& n : bvh.nodes)
      for (int c = 0; c < 2; ++c) {
        if (n.child[c] == kBvhNone) continue;
        auto inside = [&](Vec3 p) { return p.x >= n.lo[c].x && p.y >= n.lo[c].y && p.z >= n.lo[c].z && p.x <= n.hi[c].x && p.y <= n.hi[c].y && p.z <= n.hi[c].z; };
        if (n.count[c] > 0) {
          for (uint32_t i = n.child[c]; i < n.child[c] + n.count[c]; ++i) bad += !(inside(bvh.primitives[i].a) && inside(bvh.primitives[i].b) && inside(bvh.primitives[i].c));
        } else {
          const BvhNode& k = bvh.nodes[n.child[c]];
          for (int j = 0; j < 2; ++j) bad += k.child[j] != kBvhNone && !(inside(k.lo[j]) && inside(k.hi[j]));
        }
      }
    CHECK(bad == 0);
    MESSAGE(std::string("teapot: " + std::to_string(bvh.nodes.size()) + " nodes, depth " + std::to_string(bvh.depth)));
  }

  TEST_CASE("closest hits and occlusion agree with Embree on random rays (triangles and spheres)") {
    const std::string scenes[] = {shared_scene("cornell-box/scene-v4.pbrt"), shared_scene("veach-mis/scene-v4.pbrt"),
                                  own_scene("teapot.pbrt"), own_scene("many-lights.pbrt"), own_scene("mirror-glass.pbrt")};
    for (const std::string& path : scenes) {
      CAPTURE(path);
      Scene scene = load_scene(path);
      const Agreement g = compare(scene, random_rays(scene, 40000, 17));
      MESSAGE(std::string(path.substr(path.rfind('/') + 1) + ": " + std::to_string(g.hits) + " hits of " + std::to_string(g.rays) +
                          ", mismatches hit/t/occluded " + std::to_string(g.hit_mismatch) + "/" + std::to_string(g.t_mismatch) + "/" +
                          std::to_string(g.occluded_mismatch)));
      CHECK(g.hits > g.rays / 10);  // the rays do hit things: the comparison has power
      // Rays that graze a shared edge may be given to either triangle or, at float precision, to
      // neither by one of two different (both correct) triangle tests: 1 in 10000 at most (0 seen;
      // cutting 0.1% off each triangle's edge gives 21-33 mismatches).
      CHECK(g.hit_mismatch <= g.rays / 10000);
      CHECK(g.t_mismatch <= g.rays / 10000);
      CHECK(g.occluded_mismatch <= g.rays / 10000);
    }
  }

  TEST_CASE("axis-parallel rays, rays from inside spheres, and rays Embree refuses") {
    Scene scene = load_scene(own_scene("many-lights.pbrt"));
    REQUIRE(!scene.spheres.empty());
    std::vector<Ray> rays = random_rays(scene, 6000, 5);
    for (size_t i = 0; i < rays.size(); ++i) {  // snap directions to the axes
      Vec3 d(0);
      d[int(i % 3)] = (i / 3) % 2 ? 1.0f : -1.0f;
      rays[i].d = d;
    }
    for (size_t i = 0; i < scene.spheres.size() && i < 200; ++i) {  // from the centre: the far side, at t = r
      rays.push_back(Ray{scene.spheres[i].center, normalize(Vec3(0.3f, -1, 0.2f)), 0, kInfinity});
    }
    const Agreement g = compare(scene, rays);
    CHECK(g.hit_mismatch <= 2);
    CHECK(g.t_mismatch <= 2);
    CHECK(g.occluded_mismatch <= 2);
    BvhQueries bvh(scene);
    const float nan = std::nanf("");
    const std::vector<Ray> bad = {Ray{Vec3(nan), Vec3(0, 0, 1), 0, kInfinity}, Ray{Vec3(0), Vec3(0, nan, 1), 0, kInfinity},
                                  Ray{Vec3(0), Vec3(0, 0, 1), 2, 1}, Ray{Vec3(0), Vec3(0, 0, 1), -1, 1}, Ray{Vec3(2e18f, 0, 0), Vec3(-1, 0, 0), 0, kInfinity}};
    std::vector<Hit> hits(bad.size());
    std::vector<uint8_t> blocked(bad.size(), 7);
    bvh.intersect_batch(bad, hits);
    bvh.occluded_batch(bad, blocked);
    for (size_t i = 0; i < bad.size(); ++i) CHECK((!hits[i].valid() && blocked[i] == 0));
  }

  TEST_CASE("a one-triangle scene (the root is a leaf) and an empty scene") {
    Scene one;
    one.materials.emplace_back();
    TriangleMesh m;
    m.positions = {Vec3(-1, -1, 2), Vec3(1, -1, 2), Vec3(0, 1, 2)};
    m.indices = {0, 1, 2};
    one.meshes.push_back(m);
    BvhQueries q(one);
    const std::vector<Ray> rays = {Ray{Vec3(0), Vec3(0, 0, 1), 0, kInfinity}, Ray{Vec3(0), Vec3(0, 0, -1), 0, kInfinity},
                                   Ray{Vec3(0), Vec3(0, 0, 1), 0, 1.5f}};
    std::vector<Hit> hits(rays.size());
    q.intersect_batch(rays, hits);
    CHECK(hits[0].valid());
    CHECK(hits[0].t == doctest::Approx(2));
    CHECK(hits[0].u == doctest::Approx(0.25));  // (0,0) = 0.25 v0 + 0.25 v1 + 0.5 v2
    CHECK(hits[0].v == doctest::Approx(0.5));
    CHECK(!hits[1].valid());
    CHECK(!hits[2].valid());
    Scene empty;
    empty.materials.emplace_back();
    BvhQueries none(empty);
    q.intersect_batch(rays, hits);
    none.intersect_batch(rays, hits);
    CHECK(!hits[0].valid());
  }

  TEST_CASE("the path tracer through the BVH traversal renders Embree's image") {
    for (const char* rel : {"cornell-box/scene-v4.pbrt", "veach-mis/scene-v4.pbrt"}) {
      CAPTURE(rel);
      Scene scene = load_scene(shared_scene(rel));
      Options o = options_for(scene, {"film.width=64", "film.height=48", "render.spp=4"});
      Accel accel(scene);
      Lights lights(scene, o.render.light_selection);
      PerspectiveCamera cam(scene.camera.at_frame(0, 1), o.film.width, o.film.height);
      FrameInfo info;
      info.camera = &cam;
      Image embree(o.film.width, o.film.height), ours(o.film.width, o.film.height);
      make_integrator("pt", RenderContext{scene, accel, lights, o})->render_frame(info, embree);
      Options on_bvh = o;
      on_bvh.render.backend = Backend::cpu_bvh;  // the CUDA backend's code on the host
      make_integrator("pt", RenderContext{scene, accel, lights, on_bvh})->render_frame(info, ours);
      // The same random streams and the same hits up to float rounding of t (the two triangle
      // tests round differently, which moves a hit point by an ulp): the same pixels to 1e-4, but
      // for the rare path whose grazing ray or random decision the last bit turns.
      size_t differ = 0;
      for (size_t i = 0; i < embree.size(); ++i) {
        const float a = luminance(embree.pixels[i]), b = luminance(ours.pixels[i]);
        differ += std::fabs(a - b) > 1e-4f * std::max(1e-2f, std::max(a, b));
      }
      MESSAGE(std::string(std::string(rel) + ": " + std::to_string(differ) + " of " + std::to_string(embree.size()) + " pixels differ by > 1e-4"));
      CHECK(differ <= embree.size() / 500);
      CHECK(mean_channel(ours, 1) == doctest::Approx(mean_channel(embree, 1)).epsilon(2e-3));
      CHECK(mean_channel(embree, 1) > 0.01);
    }
  }

  TEST_CASE("the ray log (benchmarks) sees every query once, scalar and batched; a DI frame's closest hits are its primary rays") {
    const Scene scene = load_scene(shared_scene("cornell-box/scene-v4.pbrt"));
    Accel accel(scene);
    const std::vector<Ray> rays = random_rays(scene, 20, 5);
    RayLog log;
    Hit hit;
    (void)accel.intersect(rays[0], hit);  // before the log is set: not logged
    accel.set_ray_log(&log);
    for (int i = 0; i < 3; ++i) (void)accel.intersect(rays[size_t(i)], hit);
    for (int i = 3; i < 5; ++i) (void)accel.occluded(rays[size_t(i)]);
    std::vector<Hit> hits(5);
    std::vector<uint8_t> blocked(4);
    accel.intersect(std::span<const Ray>(rays.data() + 5, 5), hits);
    accel.occluded(std::span<const Ray>(rays.data() + 10, 4), blocked);
    accel.set_ray_log(nullptr);
    (void)accel.occluded(rays[15]);  // after: not logged
    const std::vector<Ray> closest = log.closest(), any_hit = log.any_hit();
    REQUIRE(closest.size() == 8);
    REQUIRE(any_hit.size() == 6);
    for (size_t i = 0; i < 8; ++i) CHECK((closest[i].o == rays[i < 3 ? i : i + 2].o && closest[i].d == rays[i < 3 ? i : i + 2].d));
    for (size_t i = 0; i < 6; ++i) CHECK(any_hit[i].d == rays[i < 2 ? i + 3 : i + 8].d);

    // ReSTIR DI without BSDF candidates traces one closest hit per pixel (its primary ray) and its
    // shadow rays; the log counts exactly that, whatever the thread count.
    Options o = options_for(scene, {"film.width=24", "film.height=16", "render.spp=1", "di.bsdf_candidates=0"});
    o.integrator = "restir-di";
    FrameRenderer renderer(scene, o);
    Image img(o.film.width, o.film.height);
    RayLog frame_log;
    renderer.set_ray_log(&frame_log);
    (void)renderer.render_frame(scene.camera.at_frame(0, 1), 1, img, nullptr);
    CHECK(frame_log.closest().size() == size_t(24 * 16));
    // At most one visibility ray per initial sample and two per spatial neighbour (pairwise MIS).
    CHECK(frame_log.any_hit().size() > 0);
    CHECK(frame_log.any_hit().size() <= size_t(24 * 16) * size_t(1 + 2 * o.di.reuse.spatial_neighbors));
  }

  TEST_CASE("render.backend=cuda without a usable device is one clear option error") {
    if (cuda_unavailable_reason().empty()) return;  // a GPU machine: restir_gpu_tests covers it
    Scene scene = load_scene(shared_scene("cornell-box/scene-v4.pbrt"));
    Options o = options_for(scene, {"film.width=8", "film.height=8", "render.backend=cuda"});
    CHECK_THROWS_WITH_AS(FrameRenderer(scene, o), doctest::Contains("render.backend = cuda"), OptionError);
    o.integrator = "restir-pt";  // the ReSTIR drivers on CUDA need the device too
    o.path.max_depth = 5;        // (the scene asks for 65 bounces: more than ReSTIR PT and GI render)
    CHECK_THROWS_WITH_AS(FrameRenderer(scene, o), doctest::Contains("render.backend = cuda"), OptionError);
    o.integrator = "restir-gi";
    CHECK_THROWS_WITH_AS(FrameRenderer(scene, o), doctest::Contains("render.backend = cuda"), OptionError);
    o.integrator = "ssr";  // every integrator runs on every backend (issue 48: ssr too)
    CHECK_THROWS_WITH_AS(FrameRenderer(scene, o), doctest::Contains("render.backend = cuda"), OptionError);
  }
}
