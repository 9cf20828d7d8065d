// ReSTIR PT Enhanced's footprint reconnection criterion (Lin, Kettunen, Wyman 2026, sec. 4, eq. 5;
// walk.h): the primary footprint, the forward and inverse ray footprints and the single-vertex
// roughness on hand-computed cases, and the option.
#include <doctest/doctest.h>

#include "test_helpers.h"
#include "criterion_vertices.h"
#include "integrators/restir_pt/walk.h"

using namespace rl;
using namespace rl::pt_detail;
using namespace rl::test;

namespace {

PathSettings footprint_settings(float c = 0.02f) {
  PathSettings ps;
  ps.pt.reconnection = Reconnection::footprint;
  ps.pt.footprint_threshold = c;
  return ps;
}

Bsdf diffuse() { return Bsdf{}; }

}  // namespace

TEST_SUITE("restir_pt_footprint") {
  TEST_CASE("primary footprint: |x1 - x0|^2 4 pi / |cos| and the threshold c/100 of it (eq. 5's right side)") {
    GSurface s;
    s.valid = true;
    s.depth = 2;
    s.ng = Vec3(0, 0, 1);
    s.wo = Vec3(0.6f, 0, 0.8f);  // cos 0.8
    CHECK(primary_footprint(s) == doctest::Approx(4 * 4 * kPi / 0.8));  // 20 pi
    CHECK(footprint_threshold(footprint_settings(), s) == doctest::Approx(0.0002 * 20 * kPi));
    CHECK(footprint_threshold(footprint_settings(1), s) == doctest::Approx(0.01 * 20 * kPi));
    // Under roughness-distance there is no threshold; at grazing view the cosine is floored.
    CHECK(footprint_threshold(PathSettings{}, s) == 0);
    s.wo = Vec3(1, 0, 0);
    CHECK(primary_footprint(s) == doctest::Approx(4 * 4 * kPi / 1e-6).epsilon(1e-4));
  }

  TEST_CASE("forward ray footprint: a diffuse lobe's (p G)^-1 = pi d^2 / cos_b against the threshold") {
    const PathSettings ps = footprint_settings();
    // a: diffuse at the origin facing +z, lit from +z; the direction a -> b straight up: p = cos/pi = 1/pi.
    const Vertex a = vertex(Vec3(0), Vec3(0, 0, 1), Vec3(0, 0, 1), diffuse());
    const Vec3 up(0, 0, 1);
    CHECK(pdf_toward(ps, a, up) == doctest::Approx(1 / kPi));
    const float thr = 4 * kPi;  // the footprint of d = 2 seen head-on
    for (float d : {1.9f, 2.1f}) {
      const Vertex b = vertex(Vec3(0, 0, d), Vec3(0, 0, -1), -up, diffuse());
      CAPTURE(d);
      CHECK(pair_opens(ps, a, b, up, d, thr) == (d > 2));
      // Diffuse x_k: no inverse footprint test (fn. 6), whatever the threshold.
      CHECK(pair_completes(ps, b, a.ng, up, d, up, 1e30f));
    }
    // b tilted by 60 degrees: cos_b = 1/2 doubles the footprint, pi 1.5^2 * 2 = 4.5 pi >= 4 pi.
    const Vec3 tilted = normalize(Vec3(std::sqrt(3.0f), 0, -1));
    CHECK(std::fabs(dot(tilted, up)) == doctest::Approx(0.5));
    CHECK(pair_opens(ps, a, vertex(Vec3(0, 0, 1.5f), tilted, -up, diffuse()), up, 1.5f, thr));
    CHECK_FALSE(pair_opens(ps, a, vertex(Vec3(0, 0, 1.5f), Vec3(0, 0, -1), -up, diffuse()), up, 1.5f, thr));
    CHECK(footprint_at_least(2, 1 / kPi, 1, 4 * kPi * 0.999f));
    CHECK_FALSE(footprint_at_least(2, 1 / kPi, 1, 4 * kPi * 1.001f));
    CHECK(footprint_at_least(1, 5, 0, 1e30f));  // cos 0 (a delta light's zero normal): infinite footprint
  }

  TEST_CASE("single-vertex roughness at x_{k-1} (sec. 4.2): a smooth lobe never opens a pair, whatever its footprint") {
    PathSettings ps = footprint_settings();
    const Vec3 up(0, 0, 1);
    const Vertex b = vertex(Vec3(0, 0, 100), Vec3(0, 0, -1), -up, diffuse());
    CHECK_FALSE(pair_opens(ps, vertex(Vec3(0), up, up, conductor(0.1f)), b, up, 100, 0));
    CHECK(pair_opens(ps, vertex(Vec3(0), up, up, conductor(0.3f)), b, up, 100, 0));
    ps.pt.footprint_min_roughness = 0.5f;
    CHECK_FALSE(pair_opens(ps, vertex(Vec3(0), up, up, conductor(0.3f)), b, up, 100, 0));
    // Emitters: at infinity only the roughness counts; an area emitter's forward footprint is tested.
    ps.pt.footprint_min_roughness = 0.2f;
    const Vertex a = vertex(Vec3(0), up, up, diffuse());
    CHECK(emitter_reconnectable(ps, a, true, Vec3(0), up, 0, 1e30f, false));
    CHECK_FALSE(emitter_reconnectable(ps, vertex(Vec3(0), up, up, conductor(0.1f)), true, Vec3(0), up, 0, 0, false));
    CHECK(emitter_reconnectable(ps, a, false, Vec3(0, 0, -1), up, 2.1f, 4 * kPi, false));
    CHECK_FALSE(emitter_reconnectable(ps, a, false, Vec3(0, 0, -1), up, 1.9f, 4 * kPi, false));
    CHECK(emitter_reconnectable(ps, a, false, Vec3(0), up, 0.01f, 4 * kPi, false));  // a point light: no area density
  }

  TEST_CASE("inverse ray footprint: a GGX lobe at normal incidence, p = D(n)/4 = 1/(4 pi alpha^2)") {
    const PathSettings ps = footprint_settings();
    const Vec3 up(0, 0, 1), down(0, 0, -1);
    const Vertex a = vertex(Vec3(0), up, up, diffuse());
    const float alpha = 0.5f;  // 4 pi alpha^2 = pi: the same footprint pi d^2 as the diffuse case above
    for (float d : {1.9f, 2.1f}) {
      // x_k above a, facing it, reflecting straight back toward a (its outgoing direction -up).
      const Vertex b = vertex(Vec3(0, 0, d), down, down, conductor(alpha));
      CHECK(pdf_toward(ps, b, down) == doctest::Approx(1 / (4 * kPi * alpha * alpha)).epsilon(1e-4));
      CAPTURE(d);
      CHECK(pair_completes(ps, b, a.ng, up, d, down, 4 * kPi) == (d > 2));
      CHECK(pair_opens(ps, a, b, up, d, 4 * kPi) == (d > 2));
    }
    // Under roughness-distance nothing is left for b's event to decide.
    const Vertex b = vertex(Vec3(0, 0, 1), down, down, conductor(alpha));
    CHECK(pair_completes(PathSettings{}, b, a.ng, up, 1, down, 1e30f));
    CHECK_FALSE(inverse_tested(PathSettings{}, b));
    CHECK(inverse_tested(ps, b));
    CHECK_FALSE(inverse_tested(ps, a));
  }

  TEST_CASE("options: pt.reconnection, pt.footprint_threshold, pt.footprint_min_roughness") {
    Options o;
    CHECK(o.pt.reconnection == Reconnection::roughness_distance);
    CHECK(o.pt.footprint_threshold == 0.02f);
    CHECK(o.pt.footprint_min_roughness == 0.2f);
    set_option(o, "pt.reconnection", "footprint");
    set_option(o, "pt.footprint_threshold", "0.5");
    set_option(o, "pt.footprint_min_roughness", "0.3");
    CHECK(o.pt.reconnection == Reconnection::footprint);
    CHECK(o.pt.footprint_threshold == 0.5f);
    CHECK(o.pt.footprint_min_roughness == 0.3f);
    CHECK_THROWS(set_option(o, "pt.reconnection", "nearby"));
    const PathSettings ps = path_settings(o);
    CHECK(ps.pt.reconnection == Reconnection::footprint);
  }
}
