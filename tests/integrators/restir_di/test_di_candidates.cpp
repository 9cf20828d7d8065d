// ReSTIR DI's batched light candidates (di_candidates.h) against the one-candidate-at-a-time path
// they replace: LightsView::sample_emitter, view_light, di_value and the strategies' densities.
// The batch promises the same numbers bit for bit, so the comparisons are exact.
#include <doctest/doctest.h>

#include "core/rng.h"
#include "integrators/restir_di/di_candidates.h"
#include "scene/lights.h"

using namespace rl;

namespace {

Scene candidate_scene() {
  Scene scene;
  scene.materials.push_back(Material{});
  auto quad = [&](Vec3 o, Vec3 a, Vec3 b, Rgb le, bool two_sided) {
    TriangleMesh m;
    m.positions = {o, o + a, o + a + b, o + b};
    m.indices = {0, 1, 2, 0, 2, 3};
    m.emission = AreaEmission{le, two_sided};
    scene.meshes.push_back(m);
  };
  quad({-1, 3, -1}, {2, 0, 0}, {0, 0, 2}, Rgb(4, 3, 2), false);    // one-sided, facing down or up
  quad({2, 0.5f, -1}, {0, 1, 0}, {0, 0, 1.5f}, Rgb(1, 2, 3), true);  // two-sided, edge-on to some receivers
  quad({-3, 1, 2}, {1, 0, 0}, {0, 1, 0}, Rgb(0), false);              // black: never a sample
  auto sphere = [&](Vec3 c, float r, Rgb le, bool flip) {
    Sphere s;
    s.center = c, s.radius = r, s.emission = AreaEmission{le, false}, s.flip_normal = flip;
    scene.spheres.push_back(s);
  };
  sphere({0, 2, 1}, 0.3f, Rgb(20, 10, 5), false);
  sphere({-2, 1.5f, -1}, 0.5f, Rgb(3), true);       // inward normals: lights only from inside
  sphere({40, 30, 60}, 0.05f, Rgb(5000), false);    // far and tiny: the Taylor branch of the cone
  sphere({0.2f, 0.4f, 0.1f}, 1.0f, Rgb(2), false);  // contains some receivers: the scalar path
  sphere({3, 3, 3}, 0.4f, Rgb(0), false);           // black
  scene.point_lights.push_back({{1, 2, -2}, Rgb(6)});
  EnvironmentLight env;
  env.radiance = Rgb(0.25f);
  scene.environment = env;
  return scene;
}

GSurface surface(Vec3 p, Vec3 n, Vec3 wo, const Bsdf& bsdf) {
  GSurface s;
  s.valid = true;
  s.p = p;
  s.ng = s.ns = normalize(n);
  s.wo = normalize(wo);
  s.bsdf = bsdf;
  return s;
}

}  // namespace

TEST_SUITE("restir_di") {
  TEST_CASE("batched light candidates equal the one-at-a-time evaluation bit for bit (spheres, triangles, every BSDF)") {
    const Scene scene = candidate_scene();
    const Lights lights(scene, LightSelection::power);
    const LightsView& view = lights.view();
    Bsdf diffuse;
    diffuse.reflectance = Rgb(0.7f, 0.5f, 0.3f);
    Bsdf rough_metal;
    rough_metal.type = Material::Type::conductor;
    rough_metal.eta = Rgb(0.2f, 0.9f, 1.1f), rough_metal.k = Rgb(3.9f, 2.4f, 2.1f);
    rough_metal.alpha_x = 0.3f, rough_metal.alpha_y = 0.15f;
    Bsdf glass;
    glass.type = Material::Type::dielectric;
    glass.alpha_x = glass.alpha_y = 0.4f;
    const GSurface receivers[] = {
        surface({0, 0, 0}, {0, 1, 0}, {0.3f, 1, -0.5f}, diffuse),
        surface({0.5f, 0.2f, 0.3f}, {0.2f, 1, 0.1f}, {0, 1, 1}, diffuse),  // inside the unit sphere
        surface({1, 1, -0.5f}, {-1, 0.2f, 0.3f}, {-1, 0.5f, 0}, rough_metal),
        surface({-1, 0.5f, 1}, {0, 0, -1}, {0.1f, 0.2f, -1}, glass),
        surface({0, 0, 0}, {0, -1, 0}, {0, 1, 0}, diffuse),  // seen from behind
    };
    Pcg32 rng(2024);
    int batched = 0, scalar = 0, lit = 0, compared = 0;
    for (const GSurface& s : receivers) {
      const Vec3 wo_l = s.frame().to_local(s.wo);
      for (int round = 0; round < 200; ++round) {
        DiCandidateBatch b;
        b.n = 1 + int(rng.next_float() * kDiCandidateBatch) % kDiCandidateBatch;
        for (int i = 0; i < b.n; ++i) {
          b.emitter[i] = uint32_t(std::min<size_t>(lights.emitter_count() - 1, size_t(rng.next_float() * float(lights.emitter_count()))));
          b.pmf[i] = view.selection_pmf(b.emitter[i]);
          b.ux[i] = rng.next_float(), b.uy[i] = rng.next_float();
        }
        const uint32_t left = di_eval_light_candidates(view, s, wo_l, true, b);
        for (int i = 0; i < b.n; ++i) {
          const uint32_t e = b.emitter[i];
          const LightKind kind = view.kind(e);
          if (left & (1u << i)) {  // only what the batch does not cover is left to the scalar path
            ++scalar;
            const bool inside = length_squared(s.p - view.emitters[e].p0) <= view.emitters[e].radius * view.emitters[e].radius;
            CHECK((kind == LightKind::point || kind == LightKind::environment || (kind == LightKind::sphere && inside)));
            continue;
          }
          ++batched;
          CAPTURE(e);
          CAPTURE(i);
          LightSample ls;
          const bool ok = lights.sample_emitter(e, s.p, Vec2{b.ux[i], b.uy[i]}, ls);
          REQUIRE(b.valid[i] == ok);
          if (!ok) {
            CHECK(b.target[i] == 0);
            continue;
          }
          const LightPoint y{ls.position, e};
          di_detail::LightView v;
          const bool seen = di_detail::view_light(view, s, y, v);
          const float t = seen ? luminance(di_detail::di_value(s, wo_l, v)) : 0.0f;
          CHECK(b.qx[i] == ls.position.x);
          CHECK(b.qy[i] == ls.position.y);
          CHECK(b.qz[i] == ls.position.z);
          CHECK(b.target[i] == t);
          if (t > 0) {
            ++lit;
            CHECK(b.light_pdf[i] == ls.pdf * b.pmf[i] * v.g);
            CHECK(b.bsdf_pdf[i] == bsdf_pdf(s.bsdf, wo_l, v.wi_l) * v.g);
          }
          ++compared;
        }
      }
    }
    MESSAGE("batched ", batched, " (", compared, " sampled, ", lit, " lit), scalar ", scalar);
    CHECK(batched > 3000);  // every kind and receiver was exercised
    CHECK(lit > 1000);
    CHECK(scalar > 300);
  }
}
