// Issue 48: the compressed 8-wide BVH (Ylitie, Karras & Laine 2017; backends/wide_bvh.h), proved
// on the CPU: its nodes hold their subtrees (decoded boxes outward of the exact ones, and not much
// larger), every primitive once, meta and masks consistent; its traversal returns the binary
// tree's hits on random rays (and Embree's), at the edge cases; and every integrator on the host
// twin renders the binary tree's images, animated scenes included.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "backends/bvh.h"
#include "backends/bvh_queries.h"
#include "backends/bvh_traverse.h"
#include "backends/cpu/accel.h"
#include "frame/render.h"
#include "query_agreement.h"
#include "random_rays.h"
#include "test_helpers.h"

using namespace rl;
using namespace rl::test;

namespace {

struct Box {
  Vec3 lo, hi;
  bool holds(Vec3 p) const { return p.x >= lo.x && p.y >= lo.y && p.z >= lo.z && p.x <= hi.x && p.y <= hi.y && p.z <= hi.z; }
};

Box decoded(const WideBvhNode& n, int s) {
  Box b;
  for (int a = 0; a < 3; ++a) {
    const float step = wide_bvh_step(n.exponent[a]), p = n.origin[a];
    b.lo[a] = wide_bvh_decode(p, step, n.lo[a][s]);
    b.hi[a] = wide_bvh_decode(p, step, n.hi[a][s]);
  }
  return b;
}

// Walks the tree from `node`: every slot's decoded box holds what lies below it (checked against
// the exact boxes of the primitives), meta agrees with the inner mask, leaves take 1-3
// primitives at offsets inside the node's 24, and each primitive is reached once. Returns the
// exact box of the subtree. `slack` collects, per slot, how much wider than the exact box the
// decoded box is, in grid steps (the quantization must round outwards, by less than a step).
struct TreeCheck {
  const Bvh& bvh;
  std::vector<int> seen;
  size_t bad_box = 0, bad_meta = 0;
  double max_slack_steps = 0;

  Box walk(uint32_t index) {
    const WideBvhNode& n = bvh.wide_nodes[index];
    Box all{Vec3(kInfinity), Vec3(-kInfinity)};
    uint32_t inner = 0;
    for (int s = 0; s < kWideBvhWidth; ++s) {
      const uint32_t meta = n.meta[s];
      const bool is_inner = (n.inner_mask >> s) & 1;
      if (meta == 0) {
        bad_meta += is_inner;
        continue;
      }
      Box exact{Vec3(kInfinity), Vec3(-kInfinity)};
      if (is_inner) {
        bad_meta += meta != ((1u << 5) | (24u + uint32_t(s)));
        // The inner children before this slot come first (the traversal's popcount).
        const uint32_t before = uint32_t(__builtin_popcount(n.inner_mask & ((1u << s) - 1)));
        bad_meta += before != inner;
        exact = walk(n.child_base + inner++);
      } else {
        const uint32_t unary = meta >> 5, offset = meta & 31;
        const int count = unary == 1 ? 1 : unary == 3 ? 2 : unary == 7 ? 3 : 0;
        bad_meta += count == 0 || offset + uint32_t(count) > 24;
        for (int i = 0; i < count; ++i) {
          const uint32_t p = n.primitive_base + offset + uint32_t(i);
          if (p >= bvh.primitives.size()) {
            ++bad_meta;
            continue;
          }
          ++seen[p];
          const Bounds3 b = primitive_bounds(bvh.primitives[p], bvh.sphere_geom);
          exact.lo = min(exact.lo, b.lo), exact.hi = max(exact.hi, b.hi);
        }
      }
      const Box q = decoded(n, s);
      bad_box += !(q.holds(exact.lo) && q.holds(exact.hi));
      for (int a = 0; a < 3; ++a) {
        const double step = wide_bvh_step(n.exponent[a]);
        max_slack_steps = std::max({max_slack_steps, (double(exact.lo[a]) - q.lo[a]) / step, (double(q.hi[a]) - exact.hi[a]) / step});
      }
      all.lo = min(all.lo, exact.lo), all.hi = max(all.hi, exact.hi);
    }
    return all;
  }
};

using Agreement = QueryAgreement;

// Does the ray hit the scene primitive (geom, prim) of the tree at exactly distance t?
bool hits_at(const Bvh& bvh, const Ray& ray, const Hit& h) {
  for (uint32_t i = 0; i < bvh.primitives.size(); ++i)
    if (bvh.primitives[i].geom == h.geom && bvh.primitives[i].prim == h.prim) {
      float tmax = ray.tmax;
      Hit found;
      return bvh_primitive_hit(bvh.view(), i, ray, ray.tmin, tmax, &found) && found.t == h.t;
    }
  return false;
}

// The wide tree's answers against another query's: the same hit or miss and occlusion; on the
// same primitive the same t, u, v (exact_t: bit for bit, as the two trees test primitives with the
// same code; else within 1e-4 as for Embree). Another primitive is a tie when the wide tree's
// primitive really lies at its t and that is the other's t to a few ulps: coplanar surfaces
// (the Cornell box's and many-lights' overlapping quads), where which one a float box test
// lets through first decides.
Agreement compare(const RayQueries& reference, const BvhQueries& wide, const std::vector<Ray>& rays, bool exact_t) {
  return compare_queries(reference, wide, rays, [&](size_t i, const Hit& a, const Hit& b, Agreement& g) {
    const bool same_primitive = a.geom == b.geom && a.prim == b.prim;
    const float tolerance = exact_t && same_primitive ? 0.0f : (exact_t ? 1e-6f : 1e-4f) * std::max(1.0f, a.t);
    const bool same_t = std::fabs(a.t - b.t) <= tolerance;
    if (!same_t) {
      ++g.t_mismatch;
    } else if (same_primitive) {
      g.t_mismatch += exact_t && (a.u != b.u || a.v != b.v);  // the same test: the same barycentrics
    } else if (hits_at(wide.bvh(), rays[i], b)) {
      ++g.ties;
    } else {
      ++g.t_mismatch;
    }
  });
}

const char* kScenes[] = {"cornell-box/scene-v4.pbrt", "veach-mis/scene-v4.pbrt", "teapot.pbrt", "many-lights.pbrt", "mirror-glass.pbrt", "teapot-field.pbrt"};

std::string scene_path(const std::string& rel) { return rel.find('/') != std::string::npos ? shared_scene(rel) : own_scene(rel); }

}  // namespace

TEST_SUITE("bvh") {
  TEST_CASE("wide BVH: every primitive once, decoded boxes hold their subtrees within a grid step, meta and masks agree") {
    for (const char* rel : kScenes) {
      CAPTURE(rel);
      const Scene scene = load_scene(scene_path(rel));
      const Bvh wide = build_bvh(scene, BvhLayout::wide);
      const Bvh binary = build_bvh(scene, BvhLayout::binary);
      REQUIRE(wide.primitives.size() == scene.triangle_count() + scene.spheres.size());
      REQUIRE(!wide.wide_nodes.empty());
      CHECK(wide.nodes.empty());
      CHECK(wide.depth <= kBvhMaxDepth);
      TreeCheck t{wide, std::vector<int>(wide.primitives.size(), 0)};
      t.walk(0);
      CHECK(std::all_of(t.seen.begin(), t.seen.end(), [](int c) { return c == 1; }));
      CHECK(t.bad_box == 0);
      CHECK(t.bad_meta == 0);
      // Outward rounding moves a face by less than one step (up to float rounding of p + q 2^e,
      // and a coarser step where that rounding forced one: at most two).
      CHECK(t.max_slack_steps <= 2.0);
      // The point of the layout: under half the nodes (leaves of 3 primitives, not 4, keep it
      // from a quarter), half the depth, and fewer bytes of nodes.
      CHECK(wide.wide_nodes.size() * 2 <= binary.nodes.size());
      CHECK(wide.depth * 3 <= binary.depth * 2);
      CHECK(wide.node_bytes() < binary.node_bytes());
      MESSAGE(std::string(std::string(rel) + ": " + std::to_string(wide.wide_nodes.size()) + " wide nodes (" + std::to_string(wide.node_bytes()) +
              " B, depth " + std::to_string(wide.depth) + ") vs " + std::to_string(binary.nodes.size()) + " binary (" +
              std::to_string(binary.node_bytes()) + " B, depth " + std::to_string(binary.depth) + "); max slack " +
              std::to_string(t.max_slack_steps) + " steps"));
    }
  }

  TEST_CASE("wide BVH: the binary tree's closest hits (t bit for bit, but coplanar ties) and occlusion on random rays, and Embree's") {
    for (const char* rel : kScenes) {
      CAPTURE(rel);
      const Scene scene = load_scene(scene_path(rel));
      const std::vector<Ray> rays = random_rays(scene, 30000, 23);
      const BvhQueries wide(scene, BvhLayout::wide), binary(scene, BvhLayout::binary);
      const Accel embree(scene);
      const Agreement g = compare(binary, wide, rays, true);
      const Agreement e = compare(embree, wide, rays, false);
      MESSAGE(std::string(std::string(rel) + ": " + std::to_string(g.hits) + " hits of " + std::to_string(g.rays) + "; vs binary hit/t/occluded " +
              std::to_string(g.hit_mismatch) + "/" + std::to_string(g.t_mismatch) + "/" +
              std::to_string(g.occluded_mismatch) + ", coplanar ties " + std::to_string(g.ties) + "; vs Embree " + std::to_string(e.hit_mismatch) + "/" + std::to_string(e.t_mismatch) +
              "/" + std::to_string(e.occluded_mismatch)));
      CHECK(g.hits > g.rays / 10);  // the rays hit things: the comparison has power
      CHECK(g.hit_mismatch == 0);
      CHECK(g.t_mismatch == 0);
      CHECK(g.ties <= g.hits / 200);  // measured: at most 0.15% (many-lights)
      CHECK(g.occluded_mismatch == 0);
      // Embree's triangle test rounds differently (test_bvh.cpp: 1 in 10000 at most).
      CHECK(e.hit_mismatch <= e.rays / 10000);
      CHECK(e.t_mismatch <= e.rays / 10000);
      CHECK(e.occluded_mismatch <= e.rays / 10000);
    }
  }

  TEST_CASE("wide BVH: axis-parallel rays, rays from inside spheres, refused rays, one triangle, an empty scene") {
    const Scene scene = load_scene(own_scene("many-lights.pbrt"));
    std::vector<Ray> rays = random_rays(scene, 6000, 5);
    for (size_t i = 0; i < rays.size(); ++i) {
      Vec3 d(0);
      d[int(i % 3)] = (i / 3) % 2 ? 1.0f : -1.0f;
      rays[i].d = d;
    }
    // The same with negative zeros (-0's inverse is -1e30: the near plane must follow its sign).
    for (size_t i = 0; i < 6000; ++i) {
      Ray r = rays[i];
      for (int c = 0; c < 3; ++c)
        if (r.d[c] == 0) r.d[c] = -0.0f;
      rays.push_back(r);
    }
    for (size_t i = 0; i < scene.spheres.size() && i < 200; ++i) rays.push_back(Ray{scene.spheres[i].center, normalize(Vec3(0.3f, -1, 0.2f)), 0, kInfinity});
    const BvhQueries wide(scene, BvhLayout::wide), binary(scene, BvhLayout::binary);
    const Agreement g = compare(binary, wide, rays, true);
    CHECK(g.hits > rays.size() / 10);
    CHECK(g.hit_mismatch == 0);
    CHECK(g.t_mismatch == 0);
    CHECK(g.occluded_mismatch == 0);
    const float nan = std::nanf("");
    const std::vector<Ray> bad = {Ray{Vec3(nan), Vec3(0, 0, 1), 0, kInfinity}, Ray{Vec3(0), Vec3(0, nan, 1), 0, kInfinity},
                                  Ray{Vec3(0), Vec3(0, 0, 1), 2, 1}, Ray{Vec3(2e18f, 0, 0), Vec3(-1, 0, 0), 0, kInfinity}};
    std::vector<Hit> hits(bad.size());
    std::vector<uint8_t> blocked(bad.size(), 7);
    wide.intersect_batch(bad, hits);
    wide.occluded_batch(bad, blocked);
    for (size_t i = 0; i < bad.size(); ++i) CHECK((!hits[i].valid() && blocked[i] == 0));

    Scene one;  // the root is a leaf: a root node with one leaf child
    one.materials.emplace_back();
    TriangleMesh m;
    m.positions = {Vec3(-1, -1, 2), Vec3(1, -1, 2), Vec3(0, 1, 2)};
    m.indices = {0, 1, 2};
    one.meshes.push_back(m);
    const BvhQueries q(one, BvhLayout::wide);
    CHECK(q.bvh().wide_nodes.size() == 1);
    const std::vector<Ray> probes = {Ray{Vec3(0), Vec3(0, 0, 1), 0, kInfinity}, Ray{Vec3(0), Vec3(0, 0, -1), 0, kInfinity},
                                     Ray{Vec3(0), Vec3(0, 0, 1), 0, 1.5f}};
    std::vector<Hit> h(probes.size());
    q.intersect_batch(probes, h);
    CHECK(h[0].valid());
    CHECK(h[0].t == doctest::Approx(2));
    CHECK(h[0].u == doctest::Approx(0.25));
    CHECK(h[0].v == doctest::Approx(0.5));
    CHECK(!h[1].valid());
    CHECK(!h[2].valid());
    Scene empty;
    empty.materials.emplace_back();
    const BvhQueries none(empty, BvhLayout::wide);
    CHECK(none.bvh().view().node_count == 0);
    none.intersect_batch(probes, h);
    CHECK(!h[0].valid());
  }

  TEST_CASE("wide BVH: every integrator on cpu-bvh renders the binary tree's images, animated scenes too; cpu refuses it") {
    struct Case {
      const char* scene;
      std::vector<const char*> sets;
    };
    const Case cases[] = {
        {"teapot.pbrt", {"integrator=pt", "path.max_depth=5"}},
        {"many-lights.pbrt", {"integrator=restir-di", "render.frames=3"}},
        {"teapot.pbrt", {"integrator=restir-gi", "path.max_depth=3", "render.frames=2"}},
        {"teapot.pbrt", {"integrator=restir-pt", "render.frames=3"}},
        {"mirror-floor.pbrt", {"integrator=ssr"}},
        {"dynamic-room.pbrt", {"integrator=restir-pt", "render.frames=4", "path.max_depth=3", "pt.shift=random-replay"}},  // the BVH rebuilt each frame
        {"moving-glossy.pbrt", {"integrator=restir-di", "render.frames=4"}},
    };
    for (const Case& c : cases) {
      CAPTURE(c.scene);
      CAPTURE(c.sets.front());
      const Scene scene = load_scene(own_scene(c.scene));
      Options o = options_for(scene, {"film.width=48", "film.height=32", "render.spp=1", "render.backend=cpu-bvh"});
      for (const char* s : c.sets) set_option_assignment(o, s);
      const RenderResult binary = render(scene, o);
      o.render.bvh = BvhLayout::wide;
      const RenderResult wide = render(scene, o);
      // The same hits (t bit for bit; ids but for ties): the same images, pixel for pixel.
      size_t differ = 0;
      double sum = 0;
      for (size_t i = 0; i < binary.average.size(); ++i) {
        differ += !(binary.average.pixels[i] == wide.average.pixels[i]);
        sum += luminance(binary.average.pixels[i]);
      }
      MESSAGE(std::string(std::string(c.scene) + " " + c.sets.front() + ": " + std::to_string(differ) + " of " + std::to_string(binary.average.size()) + " pixels differ"));
      CHECK(sum > 0);
      CHECK(differ <= binary.average.size() / 1000);
    }
    const Scene scene = load_scene(own_scene("teapot.pbrt"));
    Options o = options_for(scene, {"film.width=8", "film.height=8", "render.bvh=wide"});
    CHECK_THROWS_WITH_AS(FrameRenderer(scene, o), doctest::Contains("render.bvh = wide"), OptionError);
  }
}
