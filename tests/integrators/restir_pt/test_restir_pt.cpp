#include <doctest/doctest.h>

#include <algorithm>

#include "convergence.h"
#include "loader_test_utils.h"
#include "pt_fixture.h"
#include "image/metrics.h"
#include "integrators/path/path_tracer.h"
#include "integrators/restir_gi/restir_gi_pixel.h"
#include "integrators/restir_pt/pt_path.h"
#include "integrators/restir_pt/restir_pt_pixel.h"
#include "restir/shift.h"
#include "backends/cpu/accel.h"

using namespace rl;
using namespace rl::test;

namespace {

using Fixture = PtFixture;

// The path tracer's reference for ReSTIR PT options o: one frame of 2048 spp, o's path length.
Options path_traced(const Options& o) {
  Options r = o;
  r.integrator = "pt";
  r.render.spp = 2048;
  r.render.frames = 1;
  return only_read_keys(r);
}

bool close_rgb(Rgb a, Rgb b, float rel) {
  for (int c = 0; c < 3; ++c)
    if (std::fabs(a[c] - b[c]) > rel * std::max({std::fabs(a[c]), std::fabs(b[c]), 1e-6f})) return false;
  return true;
}

// pt.reconnection = footprint with c = footprint_c when footprint_c > 0 (else roughness-distance).
void set_footprint(PathSettings& ps, float footprint_c) {
  if (footprint_c <= 0) return;
  ps.pt.reconnection = Reconnection::footprint;
  ps.pt.footprint_threshold = footprint_c;
}

// Shifts paths between random pixel pairs and back; returns how many round trips were checked.
int check_round_trips(Fixture& fx, ShiftMapping shift, int max_depth, float footprint_c = 0, void (*tweak)(PathSettings&) = nullptr) {
  PathSettings ps;
  ps.path.russian_roulette = false;  // the walks' own default before PathSettings was made of the options
  ps.pt.shift = shift;
  ps.path.max_depth = max_depth;
  set_footprint(ps, footprint_c);
  if (tweak) tweak(ps);
  Pcg32 rng(42);
  int checked = 0, identity = 0;
  for (int it = 0; it < 3000 && checked < 200; ++it) {
    const GSurface& a = fx.random_surface(rng);
    const GSurface& b = fx.random_surface(rng);
    if (!a.valid || !b.valid) continue;
    PathReservoir r = initial_path_reservoir(fx.world(), fx.tracer(), ps, a, rng.next_u32(), 1);
    if (!r.has_sample()) continue;
    const PathSample& base = r.sample;
    CHECK(luminance(base.contribution) == doctest::Approx(r.target));
    // Onto its own pixel every shift is the identity with jacobian 1.
    PathSample same;
    float j_same = 0;
    if (shift_path(fx.world(), fx.tracer(), ps, base, a, same, j_same)) {
      ++identity;
      CHECK(j_same == doctest::Approx(1).epsilon(1e-3).scale(1e-9));
      CHECK(close_rgb(same.contribution, base.contribution, 2e-3f));
    }
    PathSample there, back;
    float j1 = 0, j2 = 0;
    if (!shift_path(fx.world(), fx.tracer(), ps, base, b, there, j1)) continue;
    REQUIRE(shift_path(fx.world(), fx.tracer(), ps, there, a, back, j2));  // invertible where defined
    ++checked;
    CHECK(j1 * j2 == doctest::Approx(1).epsilon(2e-3).scale(1e-9));
    CHECK(close_rgb(back.contribution, base.contribution, 5e-3f));
    CHECK(back.replay_pdf == doctest::Approx(base.replay_pdf).epsilon(5e-3).scale(1e-9));
    CHECK(back.rc_geometry == doctest::Approx(base.rc_geometry).epsilon(1e-3).scale(1e-9));
  }
  CHECK(identity > 0);
  return checked;
}

// combine() reads a neighbour's p̂_{←i}(x) at x = T_{i→0}(y) as its stored p̂_i(y) / |∂T_{i→0}/∂y|
// (mis.h: stored_target_valid) instead of the bridge's target_from(i, x), which shifts x back.
// Checks on random pixel pairs that the two agree, for samples of both generations: an initial path
// (its target from the walk) and a path already shifted once (its target from a shift). Returns the
// largest relative difference seen; `checked` counts the pairs.
float stored_target_error(Fixture& fx, ShiftMapping shift, int max_depth, int& checked, float footprint_c = 0,
                          void (*tweak)(PathSettings&) = nullptr) {
  PathSettings ps;
  ps.path.russian_roulette = false;  // the walks' own default before PathSettings was made of the options
  ps.pt.shift = shift;
  ps.path.max_depth = max_depth;
  set_footprint(ps, footprint_c);
  if (tweak) tweak(ps);
  const PathWorld world = path_world(*fx.ctx);
  Pcg32 rng(1234);
  float worst = 0;
  checked = 0;
  // y (target t_y) in domain `from`, shifted to `to`: stored t_y / j against the bridge's shift back.
  auto compare = [&](const PathSample& y, float t_y, const GSurface& from, const GSurface& to) {
    PathSample x;
    float j = 0;
    if (!shift_path(world, fx.tracer(), ps, y, to, x, j)) return;
    const GPacked* packed[2] = {nullptr, fx.packed_of(from)};
    const PtBridges<EmbreeTracer> bridges{fx.frame_world(), ps, true, PlantedBias{}, false};
    const PtBridge<EmbreeTracer> bridge = bridges(fx.surface_list(to, packed), 2, false);
    REQUIRE(bridge.stored_target_valid(1));
    const float shifted_back = bridge.target_from(1, x);
    const float stored = t_y / j;
    REQUIRE(shifted_back > 0);  // the inverse succeeds wherever the shift does
    worst = std::max(worst, std::fabs(stored - shifted_back) / shifted_back);
    ++checked;
  };
  for (int it = 0; it < 4000 && checked < 400; ++it) {
    const GSurface& a = fx.random_surface(rng);
    const GSurface& b = fx.random_surface(rng);
    const GSurface& c = fx.random_surface(rng);
    if (!a.valid || !b.valid || !c.valid) continue;
    const PathReservoir r = initial_path_reservoir(world, fx.tracer(), ps, a, rng.next_u32(), 1);
    if (!r.has_sample()) continue;
    compare(r.sample, r.target, a, b);
    PathSample at_b;
    float j = 0;
    if (shift_path(world, fx.tracer(), ps, r.sample, b, at_b, j)) compare(at_b, luminance(at_b.contribution), b, c);
  }
  return worst;
}

// A reconnection criterion of the hybrid shift (footprint c > 0, else roughness-distance; tweak:
// more settings) keeps the shift invertible: round trips on random pixel pairs (depth 3), and stored
// targets over the Jacobian equal to shifted-back ones (depth 4).
void check_hybrid_criterion(Fixture& fx, float footprint_c, void (*tweak)(PathSettings&) = nullptr) {
  CHECK(check_round_trips(fx, ShiftMapping::hybrid, 3, footprint_c, tweak) > 20);
  int checked = 0;
  const float worst = stored_target_error(fx, ShiftMapping::hybrid, 4, checked, footprint_c, tweak);
  CHECK(checked > 50);
  CHECK(worst < 2e-5f);
}

}  // namespace

TEST_SUITE("restir_pt") {
  TEST_CASE("a neighbour's stored target over the shift's jacobian is its target shifted back (every shift)") {
    for (const std::string& path : {shared_scene("cornell-box/scene-v4.pbrt"), shared_scene("veach-mis/scene-v4.pbrt"),
                                    own_scene("teapot.pbrt")}) {
      Fixture fx(path);
      for (ShiftMapping s : {ShiftMapping::reconnection, ShiftMapping::random_replay, ShiftMapping::hybrid}) {
        CAPTURE(path);
        CAPTURE(int(s));
        int checked = 0;
        const float worst = stored_target_error(fx, s, 4, checked);
        CHECK(checked > 50);
        CHECK(worst < 2e-5f);  // float rounding: 2e-7 to 1.6e-6 seen
        MESSAGE("stored target vs shifted back: " << checked << " pairs, largest relative difference " << worst);
      }
    }
    // Without the hybrid shift's invertibility check the shifts need not invert each other: the
    // bridge evaluates the target instead.
    Fixture fx(own_scene("teapot.pbrt"));
    PathSettings unchecked;
    unchecked.check_invertibility = false;
    const PtBridges<EmbreeTracer> bridges{fx.frame_world(), unchecked, true, PlantedBias{}, false};
    const PtBridge<EmbreeTracer> bridge = bridges(SurfaceList{}, 2, false);
    CHECK_FALSE(bridge.stored_target_valid(1));
    CHECK_FALSE(bridge.stored_target_valid(0));
  }

  TEST_CASE("ReSTIR GI: a neighbour's stored target over the reconnection jacobian is its target at its own point") {
    for (const std::string& path : {shared_scene("cornell-box/scene-v4.pbrt"), own_scene("teapot.pbrt")}) {
      CAPTURE(path);
      Fixture fx(path);
      const PathWorld world = path_world(*fx.ctx);
      const EmbreeTracer tracer{fx.accel.get()};
      PathOptions suffix = fx.options.path;
      suffix.max_depth = 2;
      Pcg32 rng(99);
      int checked = 0, occluded_back = 0;
      float worst = 0;
      for (int it = 0; it < 3000 && checked < 300; ++it) {
        const GSurface& a = fx.random_surface(rng);
        const GSurface& b = fx.random_surface(rng);
        if (!a.valid || !b.valid) continue;
        Rgb specular;
        const GiReservoir r = gi_initial(world, tracer, suffix, GiTarget::contribution, a, rng, specular);
        if (!r.has_sample()) continue;
        const GPacked* packed[2] = {nullptr, fx.packed_of(a)};  // canonical b, neighbour a
        const GiBridges<EmbreeTracer> bridges{fx.frame_world(), GiTarget::contribution, suffix, true};
        const GiBridge<EmbreeTracer> bridge = bridges(fx.surface_list(b, packed), 2, false);
        REQUIRE(bridge.stored_target_valid(1));
        GiSample x;
        float j = 0;
        if (!bridge.shift_to_canonical(1, r.sample, x, j)) continue;
        const float evaluated = bridge.target_from(1, x);
        if (evaluated == 0) {  // the traced sample's shadow ray back from its own point met an edge
          ++occluded_back;
          continue;
        }
        worst = std::max(worst, std::fabs(r.target / j - evaluated) / evaluated);
        ++checked;
      }
      CHECK(checked > 100);
      CHECK(occluded_back <= checked / 100);
      CHECK(worst < 2e-5f);
      MESSAGE("GI stored target vs evaluated: " << checked << " pairs, " << occluded_back << " occluded back, largest relative difference " << worst);
    }
  }

  TEST_CASE("reconnection jacobian matches finite differences of the direction map; its two halves give it too") {
    Pcg32 rng(3);
    for (int t = 0; t < 50; ++t) {
      const Vec3 xk{rng.next_float(), rng.next_float(), rng.next_float()};
      const Vec3 nk = normalize(Vec3{rng.next_float() - 0.5f, rng.next_float() - 0.5f, 1});
      const Vec3 x_prev = xk + normalize(Vec3{rng.next_float() - 0.5f, rng.next_float() - 0.5f, 1}) * (1 + 2 * rng.next_float());
      const Vec3 y_prev = xk + normalize(Vec3{rng.next_float() - 0.5f, rng.next_float() - 0.5f, 1}) * (1 + 2 * rng.next_float());
      // ω_x -> hit on the plane (x_k, n_k) -> ω_y; solid-angle ratio of a small patch (double precision).
      auto hit = [&](Vec3 d) {
        double t_hit = double(dot(xk - x_prev, nk)) / double(dot(d, nk));
        return x_prev + d * float(t_hit);
      };
      const Vec3 w0 = normalize(xk - x_prev);
      const Frame f = Frame::from_normal(w0);
      const float h = 1e-3f;
      auto omega_y = [&](float a, float b) { return normalize(hit(normalize(w0 + f.s * a + f.t * b)) - y_prev); };
      const Vec3 dya = (omega_y(h, 0) - omega_y(-h, 0)) / (2 * h), dyb = (omega_y(0, h) - omega_y(0, -h)) / (2 * h);
      const double fd = double(length(cross(dya, dyb)));  // d(solid angle) of ω_x per unit (a, b) is 1 at the centre
      const double analytic = restir::reconnection_jacobian(x_prev, y_prev, xk, nk);
      CAPTURE(t);
      CHECK(fd == doctest::Approx(analytic).epsilon(0.01).scale(1e-9));
      // ReSTIR PT's form (the sample keeps its own path's half, rc_geometry): the same Jacobian.
      const float from_halves = restir::reconnection_jacobian_from(restir::reconnection_geometry(x_prev, xk, nk),
                                                                   restir::reconnection_geometry(y_prev, xk, nk));
      CHECK(from_halves == doctest::Approx(analytic).epsilon(1e-5).scale(1e-9));
    }
    // Degenerate halves (a vertex on x_k, a segment in x_k's tangent plane, a distance whose factor
    // overflows) are 0, and a Jacobian with a 0 half is 0: the shift fails rather than divide.
    const Vec3 xk(0.5f), nk(0, 0, 1);
    CHECK(restir::reconnection_geometry(xk, xk, nk) == 0);
    CHECK(restir::reconnection_geometry(xk + Vec3(1, 0, 0), xk, nk) == 0);
    CHECK(restir::reconnection_geometry(xk + Vec3(0, 0, 1e-20f), xk, nk) == 0);
    CHECK(restir::reconnection_geometry(xk + Vec3(0, 0, 2), xk, nk) == doctest::Approx(0.25));
    CHECK(restir::reconnection_jacobian_from(0, 1) == 0);
    CHECK(restir::reconnection_jacobian_from(1, 0) == 0);
  }

  TEST_CASE("shifts: identity on the own pixel, invertible with reciprocal jacobians (rough Cornell box)") {
    Fixture fx(shared_scene("cornell-box/scene-v4.pbrt"));
    for (ShiftMapping s : {ShiftMapping::reconnection, ShiftMapping::random_replay, ShiftMapping::hybrid}) {
      CAPTURE(int(s));
      CHECK(check_round_trips(fx, s, 3) > 50);
    }
  }

  // The reservoir keeps x_k's material and texture value and rebuilds its BSDF from them (pt_path.h):
  // on a box whose walls are red/blue checkerboards, a reconnection vertex rebuilt with the wrong
  // reflectance (the material's untextured default, or another texel's) changes the identity
  // shift's contribution by far more than its 2e-3 tolerance.
  TEST_CASE("shifts: identity and invertibility with textured reconnection vertices (checkerboard box)") {
    const std::filesystem::path dir = loader_test::temp_dir();
    const std::string quad_uv = "\"point2 uv\" [0 0 1 0 1 1 0 1] \"integer indices\" [0 1 2 0 2 3]\n";
    const std::string path = loader_test::write_file(dir / "checks.pbrt",
        "LookAt 0 1 -2.5  0 1 0  0 1 0\nCamera \"perspective\" \"float fov\" 60\nWorldBegin\n"
        "Texture \"checks\" \"spectrum\" \"checkerboard\" \"float uscale\" 6 \"float vscale\" 6 "
        "\"rgb tex1\" [0.9 0.1 0.1] \"rgb tex2\" [0.1 0.1 0.9]\n"
        "AttributeBegin AreaLightSource \"diffuse\" \"rgb L\" [6 6 6]\n"
        "Shape \"trianglemesh\" \"point3 P\" [-0.4 1.99 -0.4 0.4 1.99 -0.4 0.4 1.99 0.4 -0.4 1.99 0.4] " + quad_uv +
        "AttributeEnd\n"
        "Material \"diffuse\" \"texture reflectance\" \"checks\"\n"
        // floor, back wall, left and right walls, ceiling (all facing the box's inside)
        "Shape \"trianglemesh\" \"point3 P\" [-1 0 -1 1 0 -1 1 0 1 -1 0 1] " + quad_uv +
        "Shape \"trianglemesh\" \"point3 P\" [-1 0 1 1 0 1 1 2 1 -1 2 1] " + quad_uv +
        "Shape \"trianglemesh\" \"point3 P\" [-1 0 -1 -1 0 1 -1 2 1 -1 2 -1] " + quad_uv +
        "Shape \"trianglemesh\" \"point3 P\" [1 0 -1 1 0 1 1 2 1 1 2 -1] " + quad_uv +
        "Shape \"trianglemesh\" \"point3 P\" [-1 2 -1 1 2 -1 1 2 1 -1 2 1] " + quad_uv);
    Fixture fx(path);
    REQUIRE(!fx.scene.textures.empty());
    for (ShiftMapping s : {ShiftMapping::reconnection, ShiftMapping::hybrid}) {
      CAPTURE(int(s));
      CHECK(check_round_trips(fx, s, 3) > 50);
    }
  }

  // pt.reconnection = footprint (walk.h; Lin et al. 2026, sec. 4): the hybrid shift re-tests the
  // criterion on the offset path with its own primary footprint, so it stays invertible; c = 0.02 is
  // the paper's, c = 2 a hundred times stricter (more pairs fail, more replay and pending pairs).
  TEST_CASE("footprint criterion: the hybrid shift is the identity on its own pixel and invertible (Cornell box, Veach MIS, teapots)") {
    for (const std::string& path : {shared_scene("cornell-box/scene-v4.pbrt"), shared_scene("veach-mis/scene-v4.pbrt"),
                                    own_scene("teapot.pbrt")}) {
      Fixture fx(path);
      for (float c : {0.02f, 2.0f}) {
        CAPTURE(path);
        CAPTURE(c);
        check_hybrid_criterion(fx, c);
      }
    }
  }

  // pt.roughness_proxy = pdf (Lin et al. 2026, supplement §4): x_k's roughness depends on the
  // direction it is reached from, so the offset path tests it again; under both criteria.
  TEST_CASE("pdf roughness proxy: the hybrid shift is the identity on its own pixel and invertible (Cornell box, Veach MIS, teapots)") {
    for (const std::string& path : {shared_scene("cornell-box/scene-v4.pbrt"), shared_scene("veach-mis/scene-v4.pbrt"),
                                    own_scene("teapot.pbrt")}) {
      Fixture fx(path);
      for (float c : {0.0f, 0.02f}) {
        CAPTURE(path);
        CAPTURE(c);
        check_hybrid_criterion(fx, c, [](PathSettings& ps) { ps.pt.roughness_proxy = RoughnessProxy::pdf; });
      }
    }
  }

  // ReSTIR PT Enhanced's roulette at initial sampling only and forced NEE reconnection (sec.
  // 6.2.3-6.2.4): the shifts stay bijections, so a stored target over the Jacobian is still the
  // target shifted back.
  TEST_CASE("initial-only roulette, forced NEE reconnection: a stored target over the jacobian is the target shifted back") {
    for (const std::string& path : {shared_scene("veach-mis/scene-v4.pbrt"), own_scene("teapot.pbrt")}) {
      Fixture fx(path);
      for (ShiftMapping s : {ShiftMapping::random_replay, ShiftMapping::hybrid}) {
        CAPTURE(path);
        CAPTURE(int(s));
        int checked = 0;
        const float worst = stored_target_error(fx, s, 5, checked, 0, [](PathSettings& ps) {
          ps.path.russian_roulette = true;
          ps.path.rr_min_depth = 1;
          ps.pt.roulette = Roulette::initial;
          ps.pt.force_nee_reconnection = true;
        });
        CHECK(checked > 50);
        CHECK(worst < 2e-5f);
      }
    }
  }

  TEST_CASE("shifts: identity and invertibility on glossy surfaces (Veach MIS, teapots)") {
    for (const std::string& path : {shared_scene("veach-mis/scene-v4.pbrt"), own_scene("teapot.pbrt")}) {
      Fixture fx(path);
      for (ShiftMapping s : {ShiftMapping::reconnection, ShiftMapping::random_replay, ShiftMapping::hybrid}) {
        CAPTURE(path);
        CAPTURE(int(s));
        CHECK(check_round_trips(fx, s, 3) > 20);
      }
    }
  }
}

namespace {

// Equality of every field a reservoir's paths are made of (padding left out), float by float
// (Vec3's operator==, as test_gbuffer's same_bits).
bool same_bits(const PathSample& a, const PathSample& b) {
  return a.seed == b.seed && a.length == b.length && a.nee == b.nee && a.rc == b.rc && a.rc_position == b.rc_position &&
         a.rc_emitter == b.rc_emitter && a.rc_prim == b.rc_prim && a.rc_barycentrics.x == b.rc_barycentrics.x &&
         a.rc_barycentrics.y == b.rc_barycentrics.y && a.rc_out == b.rc_out &&  // rc_out shares rc_normal's bytes, rc_emitter rc_geom's
         a.rc_suffix == b.rc_suffix && a.rc_mis == b.rc_mis && a.rc_tail_light_pdf == b.rc_tail_light_pdf &&
         a.rc_tail_measure == b.rc_tail_measure && a.rc_geometry == b.rc_geometry && a.replay_pdf == b.replay_pdf &&
         a.contribution == b.contribution;
}

}  // namespace

TEST_SUITE("restir_pt") {
  // initial_path_reservoir and shift_path are RL_WIDEST (core/widest.h): on an AVX2 machine they run
  // a copy compiled for x86-64-v3; initial_path_reservoir_in / shift_path_in called from here are
  // this file's baseline (SSE2) compile of the same code. The two must agree bit for bit, or the
  // image would depend on the machine.
  TEST_CASE("the widest-ISA copies of the path walk and the shift compute the baseline's floats") {
    Fixture fx(own_scene("teapot.pbrt"));
    const PathWorld world = path_world(*fx.ctx);
    const EmbreeTracer tracer{fx.accel.get()};
    Pcg32 rng(77);
    int walks = 0, shifts = 0;
    for (ShiftMapping shift : {ShiftMapping::reconnection, ShiftMapping::random_replay, ShiftMapping::hybrid}) {
      PathSettings ps;
      ps.path.russian_roulette = false;  // the walks' own default before PathSettings was made of the options
      ps.pt.shift = shift;
      ps.path.max_depth = 5;
      for (int it = 0; it < 300; ++it) {
        const GSurface& a = fx.random_surface(rng);
        const GSurface& b = fx.random_surface(rng);
        if (!a.valid || !b.valid) continue;
        const uint64_t seed = rng.next_u32();
        const PathReservoir wide = initial_path_reservoir(world, fx.tracer(), ps, a, seed, 2);
        const PathReservoir base = initial_path_reservoir<EmbreeTracer>(world, tracer, ps, a, seed, 2);
        CHECK(same_bits(wide.sample, base.sample));
        CHECK((wide.target == base.target && wide.weight_sum == base.weight_sum && wide.ucw == base.ucw &&
               wide.confidence == base.confidence));
        ++walks;
        if (!base.has_sample()) continue;
        PathSample to_wide, to_base;
        float j_wide = 0, j_base = 0;
        const bool ok_wide = shift_path(world, fx.tracer(), ps, base.sample, b, to_wide, j_wide);
        const bool ok_base = shift_path<EmbreeTracer>(world, tracer, ps, base.sample, b, to_base, j_base);
        REQUIRE(ok_wide == ok_base);
        if (!ok_base) continue;
        CHECK(same_bits(to_wide, to_base));
        CHECK(j_wide == j_base);
        ++shifts;
      }
    }
    CHECK(walks > 300);
    CHECK(shifts > 100);
  }

  TEST_CASE("debug view: reconnection depth is 2 for reconnection, 0 for replay, the first rough vertex for hybrid") {
    Scene scene = load_scene(own_scene("teapot.pbrt"));
    Options o = options_for(scene, {"integrator=restir-pt", "render.spp=1", "render.frames=2", "film.width=32", "film.height=18",
                                    "render.debug_view=reconnection-depth", "path.max_depth=3"});
    auto depths = [&](const char* shift) {
      set_option(o, "pt.shift", shift);
      std::vector<int> count(8, 0);
      for (const Rgb& p : render(scene, o).last.pixels) ++count[size_t(std::clamp(int(p.x), 0, 7))];
      return count;
    };
    auto rc = depths("reconnection");
    CHECK(rc[2] > 0);
    CHECK(rc[1] + rc[3] + rc[4] + rc[5] == 0);
    auto replay = depths("random-replay");
    CHECK(replay[0] == 32 * 18);
    auto hybrid = depths("hybrid");
    CHECK(hybrid[2] > 0);                                   // rough first bounces reconnect at once
    CHECK(hybrid[0] + hybrid[3] + hybrid[4] > 0);           // glossy / glass teapots defer or replay
    CHECK(hybrid[1] == 0);
    // With ReSTIR DI for the direct light (paths of 3+ vertices) the view is the paths' own too: it
    // renders (ReSTIR DI refuses the view on its own) and still shows the hybrid's reconnections.
    set_option(o, "pt.direct", "restir-di");
    auto with_di = depths("hybrid");
    CHECK(with_di[2] + with_di[3] > 0);
    CHECK(with_di[1] == 0);
  }

  TEST_CASE("a reconnection to the environment keeps the base path's radiance and density only while the lights are fixed") {
    Fixture fx(own_scene("teapot.pbrt"));  // an environment map and an area light
    REQUIRE(fx.lights->view().fixed);
    // The same scene with the map twice as bright: where the lights may change (an animated
    // environment), the shift must look the radiance up in its own frame's lights. Uniform light
    // selection keeps the environment's selection probability, and so its density, the same.
    Scene brighter = fx.scene;
    brighter.environment->radiance = brighter.environment->radiance * 2.0f;
    const Lights lights1(fx.scene, LightSelection::uniform), lights2(brighter, LightSelection::uniform);
    PathWorld world1 = path_world(*fx.ctx), world2 = world1;
    world1.lights = lights1.view();
    world2.lights = lights2.view();
    REQUIRE(world2.lights.fixed);
    // Paths x_1 -> x_2 on the environment, reconnected at k = n = 2.
    PathSettings ps;
    ps.path.russian_roulette = false;  // the walks' own default before PathSettings was made of the options
    ps.pt.shift = ShiftMapping::reconnection;
    ps.path.max_depth = 1;
    const uint32_t env = lights1.environment_emitter();
    Pcg32 rng(7);
    int checked = 0;
    for (int it = 0; it < 4000 && checked < 100; ++it) {
      const GSurface& a = fx.random_surface(rng);
      const GSurface& b = fx.random_surface(rng);
      if (!a.valid || !b.valid) continue;
      const PathReservoir r = initial_path_reservoir(world1, fx.tracer(), ps, a, rng.next_u32(), 1);
      if (!r.has_sample() || r.sample.rc != 2 || r.sample.length != 2 || r.sample.rc_emitter != env) continue;
      PathSample here, kept, looked_up;
      float j = 0, j_kept = 0, j_looked = 0;
      if (!shift_path(world1, fx.tracer(), ps, r.sample, b, here, j)) continue;
      // Fixed lights: the kept values, i.e. the base lights' (the caller's promise that they hold).
      REQUIRE(shift_path(world2, fx.tracer(), ps, r.sample, b, kept, j_kept));
      CHECK(kept.contribution == here.contribution);
      // Lights that may change: the lookup, twice the radiance, the same density and MIS weight.
      world2.lights.fixed = false;
      REQUIRE(shift_path(world2, fx.tracer(), ps, r.sample, b, looked_up, j_looked));
      world2.lights.fixed = true;
      CHECK(close_rgb(looked_up.contribution, here.contribution * 2.0f, 1e-5f));
      CHECK(j_looked == j);
      ++checked;
    }
    CHECK(checked >= 50);
    // The flag follows the scene: an animated environment makes the lights not fixed.
    Scene animated = fx.scene;
    animated.animations.emplace_back();
    animated.environment->animation = 0;
    CHECK_FALSE(Lights(animated, LightSelection::power).view().fixed);
  }
}

TEST_SUITE("slow") {
  // ReSTIR GI with reuse on the diffuse Cornell box: the equivalence test in test_restir_equivalence.cpp.

  TEST_CASE("ReSTIR GI's own samples are unbiased at contact geometry (floor-wall corner of the Cornell box)") {
    // Regression: a sample's density must be taken along the direction the sample is valued in
    // (visible point -> x_s), not along the traced ray from its offset origin; near contact the two
    // differ and the corner came out 5% too bright.
    Scene scene = load_scene(shared_scene("cornell-box/scene-v4.pbrt"));
    auto corner = [&](std::initializer_list<const char*> sets) {
      Options o = options_for(scene, {"render.sample_pattern=center", "film.width=24", "film.height=24", "render.frames=1"});
      for (const char* s : sets) set_option_assignment(o, s);
      const Image img = render(scene, o).average;
      double sum = 0;
      for (int y = 20; y < 24; ++y)
        for (int x = 20; x < 24; ++x) sum += luminance(img.at(x, y));
      return sum / 16;
    };
    const double pt = corner({"integrator=pt", "path.max_depth=2", "render.spp=40000"});
    const double gi = corner({"integrator=restir-gi", "path.max_depth=2", "gi.temporal=false", "gi.spatial_neighbors=0",
                              "render.spp=1", "render.frames=40000"});
    CHECK(gi == doctest::Approx(pt).epsilon(0.015).scale(1e-9));
  }

  TEST_CASE("ReSTIR PT converges to the path tracer for every shift (rough and glossy scenes)") {
    struct Case {
      std::string scene;
      const char* shift;
      const char* mis;
      const char* extra = "pt.direct=path";
    };
    const Case cases[] = {
        {own_scene("cornell-box.pbrt"), "reconnection", "pairwise"},
        {own_scene("cornell-box.pbrt"), "random-replay", "generalized-balance"},
        {own_scene("cornell-box.pbrt"), "hybrid", "pairwise"},
        {shared_scene("veach-mis/scene-v4.pbrt"), "reconnection", "generalized-balance"},
        {shared_scene("veach-mis/scene-v4.pbrt"), "random-replay", "pairwise"},
        {shared_scene("veach-mis/scene-v4.pbrt"), "hybrid", "generalized-balance"},
        {shared_scene("veach-mis/scene-v4.pbrt"), "hybrid", "pairwise"},
        {own_scene("cornell-box.pbrt"), "hybrid", "pairwise", "pt.direct=restir-di"},
    };
    for (const auto& c : cases) {
      Scene scene = load_scene(c.scene);
      Options o = options_for(scene, {"integrator=restir-pt", "render.spp=1", "render.frames=3", "render.sample_pattern=center",
                                      "path.max_depth=3"});
      o.film.width = o.film.height = 20;
      set_option(o, "pt.shift", c.shift);
      set_option(o, "pt.spatial_mis", c.mis);
      set_option_assignment(o, c.extra);
      BlockStats st = compare_to_reference(scene, o, path_traced(o), 20, 4, 4.5);
      CAPTURE(c.scene);
      CAPTURE(c.shift);
      CAPTURE(c.mis);
      CAPTURE(c.extra);
      CAPTURE(st.worst_z);
      CAPTURE(st.image_mean);
      CAPTURE(st.reference_mean);
      CHECK(st.outliers == 0);
      CHECK(std::fabs(st.relative_bias()) < 0.01 + 3 * st.image_se / st.reference_mean);
    }
  }
}

TEST_SUITE("slow") {
  TEST_CASE("thesis fig. 4.3 / 5.4: on glossy teapots hybrid and random replay beat reconnection at equal frame count") {
    Scene scene = load_scene(own_scene("teapot.pbrt"));
    Options o = options_for(scene, {"integrator=restir-pt", "render.spp=1", "render.frames=6", "render.sample_pattern=center",
                                    "path.max_depth=3", "film.width=80", "film.height=45"});
    const Image reference = render(scene, path_traced(o)).last;
    auto error = [&](const char* shift) {
      double sum = 0;
      for (uint64_t seed : {1, 2, 3, 4, 5, 6}) {  // average a few independent sequences
        Options t = o;
        set_option(t, "pt.shift", shift);
        t.render.seed = seed;
        sum += rel_mse(render(scene, t).last, reference);
      }
      return sum / 6;
    };
    const double reconnection = error("reconnection"), replay = error("random-replay"), hybrid = error("hybrid");
    MESSAGE("relMSE at frame 6 on the teapots: reconnection " << reconnection << ", random replay " << replay << ", hybrid " << hybrid);
    CHECK(hybrid < reconnection);
    CHECK(replay < reconnection);
  }
}
