// The black-box roughness proxy of ReSTIR PT Enhanced's supplement (Lin, Kettunen, Wyman 2026, §4,
// eq. 26; pt.roughness_proxy = pdf, path_terms.h): a vertex is rough for a pair leaving it toward ω
// when 1 / p(ω)² >= the threshold, p the solid-angle density of direction sampling there. Checked on
// hand-computed cases (a GGX lobe's peak), on every BSDF kind (diffuse always rough, delta never),
// and in the criteria it changes (x_k's part moves to pair_completes, tested on the offset path).
#include <doctest/doctest.h>

#include <cmath>

#include "test_helpers.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "criterion_vertices.h"
#include "integrators/restir_pt/walk.h"

using namespace rl;
using namespace rl::pt_detail;
using namespace rl::test;

namespace {

PathSettings proxy_settings(Reconnection criterion = Reconnection::roughness_distance) {
  PathSettings ps;
  ps.pt.roughness_proxy = RoughnessProxy::pdf;
  ps.pt.reconnection = criterion;
  return ps;
}

const Vec3 up(0, 0, 1), down(0, 0, -1);
// 15 degrees off the normal: off a GGX lobe's peak at normal incidence.
const Vec3 tilted = normalize(Vec3(std::sin(0.2618f), 0, std::cos(0.2618f)));

}  // namespace

TEST_SUITE("restir_pt_footprint") {
  TEST_CASE("pdf proxy: 1/p^2 of a GGX lobe's peak is 16 pi^2 alpha^4, so the threshold 0.2 is met from alpha ~ 0.189") {
    const PathSettings ps = proxy_settings();
    for (float alpha : {0.1f, 0.18f, 0.2f, 0.3f}) {
      CAPTURE(alpha);
      const Vertex v = vertex(Vec3(0), up, up, conductor(alpha));
      const float p = pdf_toward(ps, v, up);
      CHECK(p == doctest::Approx(1 / (4 * kPi * alpha * alpha)).epsilon(1e-4));
      const float proxy = 16 * kPi * kPi * alpha * alpha * alpha * alpha;
      CHECK(1 / (p * p) == doctest::Approx(proxy).epsilon(1e-3));
      CHECK(rough_toward(ps, v, up, 0.2f) == (alpha >= 0.19f));
      CHECK(rough_toward(ps, v, up, proxy * 0.999f));
      CHECK_FALSE(rough_toward(ps, v, up, proxy * 1.001f));
      // Off the peak the density falls and the same lobe counts as rough.
      CHECK(pdf_toward(ps, v, tilted) < p);
      if (alpha <= 0.18f) CHECK(rough_toward(ps, v, tilted, 0.2f) != rough_toward(ps, v, up, 0.2f));
    }
    // The material proxy reads the parameter alone, whatever the direction.
    const Vertex v = vertex(Vec3(0), up, up, conductor(0.15f));
    CHECK_FALSE(rough_toward(PathSettings{}, v, tilted, 0.2f));
    CHECK(rough_toward(PathSettings{}, v, tilted, 0.15f));
  }

  TEST_CASE("pdf proxy: a diffuse lobe is always rough (p <= 1/pi), a delta lobe never, on random directions and thresholds") {
    const PathSettings ps = proxy_settings();
    Pcg32 rng(7);
    int diffuse_checked = 0, delta_checked = 0;
    for (int i = 0; i < 2000; ++i) {
      const Vec3 wo = sample_uniform_sphere(Vec2(rng.next_float(), rng.next_float()));
      const Vec3 dir = sample_uniform_sphere(Vec2(rng.next_float(), rng.next_float()));
      const float thr = rng.next_float();  // the option's range is [0, 1]
      const Vertex d = vertex(Vec3(0), up, wo, Bsdf{});
      CHECK(rough_toward(ps, d, dir, thr));
      CHECK(rough_toward(ps, d, dir, 1.0f));
      ++diffuse_checked;
      for (Material::Type t : {Material::Type::conductor, Material::Type::dielectric}) {
        const Vertex s = vertex(Vec3(0), up, wo, ggx_bsdf(t, 0));
        REQUIRE(s.delta);
        CHECK_FALSE(rough_toward(ps, s, dir, 0.0f));
        ++delta_checked;
      }
    }
    CHECK(diffuse_checked == 2000);
    CHECK(delta_checked == 4000);
  }

  TEST_CASE("pdf proxy in the criteria: x_{k-1} toward x_k opens the pair, x_k toward x_{k+1} completes it (tested on the offset path)") {
    const PathSettings ps = proxy_settings();
    const PathSettings material;
    CHECK(criterion_depends_on_direction(ps));
    CHECK(criterion_depends_on_direction(proxy_settings(Reconnection::footprint)));
    CHECK_FALSE(criterion_depends_on_direction(material));
    const Vertex a = vertex(Vec3(0), up, up, Bsdf{});
    // x_k: a glossy lobe at 2 above a, facing it, seen along -up (incoming from a).
    const Vertex b = vertex(Vec3(0, 0, 2), down, down, conductor(0.15f));
    // roughness-distance: the material proxy refuses b outright; the pdf proxy leaves b to its event.
    CHECK_FALSE(pair_opens(material, a, b, up, 2, 0));
    CHECK(pair_opens(ps, a, b, up, 2, 0));
    CHECK_FALSE(pair_opens(ps, a, b, up, 0.05f, 0));  // the distance threshold (0.1) still holds
    CHECK(inverse_tested(ps, b));
    CHECK_FALSE(inverse_tested(ps, a));  // diffuse: always rough, nothing to test
    CHECK_FALSE(inverse_tested(material, b));
    CHECK_FALSE(pair_completes(ps, b, a.ng, up, 2, down, 0));   // back along its mirror direction: the peak
    CHECK(pair_completes(ps, b, a.ng, up, 2, -tilted, 0));      // 15 degrees off it: rough
    // A glossy x_{k-1}: its density toward x_k decides.
    const Vertex g = vertex(Vec3(0), up, up, conductor(0.15f));
    const Vertex d = vertex(Vec3(0, 0, 2), down, down, Bsdf{});
    CHECK_FALSE(pair_opens(ps, g, d, up, 2, 0));
    const Vertex d_off = vertex(tilted * 2, -tilted, -tilted, Bsdf{});
    CHECK(pair_opens(ps, g, d_off, tilted, 2, 0));
    // footprint: the proxy replaces the single-vertex roughness α(x_{k-1}) >= α_min (supplement §4).
    const PathSettings fp = proxy_settings(Reconnection::footprint);
    PathSettings fp_material = fp;
    fp_material.pt.roughness_proxy = RoughnessProxy::material;
    CHECK_FALSE(pair_opens(fp_material, g, d_off, tilted, 100, 0));
    CHECK(pair_opens(fp, g, d_off, tilted, 100, 0));
    CHECK_FALSE(pair_opens(fp, g, d, up, 100, 0));
    // Emitters after v: the proxy toward the light point.
    CHECK_FALSE(emitter_reconnectable(ps, g, true, Vec3(0), up, 0, 0, false));
    CHECK(emitter_reconnectable(ps, g, true, Vec3(0), tilted, 0, 0, false));
    CHECK(emitter_reconnectable(ps, g, true, Vec3(0), up, 0, 0, true) == false);  // forced NEE reconnection is off
  }

  TEST_CASE("options: pt.roughness_proxy") {
    Options o;
    CHECK(o.pt.roughness_proxy == RoughnessProxy::material);
    set_option(o, "pt.roughness_proxy", "pdf");
    CHECK(o.pt.roughness_proxy == RoughnessProxy::pdf);
    CHECK(path_settings(o).pt.roughness_proxy == RoughnessProxy::pdf);
    CHECK_THROWS(set_option(o, "pt.roughness_proxy", "lobe"));
  }
}
