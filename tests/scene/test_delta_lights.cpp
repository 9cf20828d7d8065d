// Tests of the spot and distant lights (pbrt-v4 SpotLight, DistantLight) in scene/lights_view.h
// and the pbrt-v4 parser: the falloff, sample / pdf / point_pdf consistency, the selection power,
// animation and follow(), and what the loader makes of from / to under the CTM.
#include <doctest/doctest.h>

#include <cmath>
#include <fstream>

#include "scene/animation.h"
#include "scene/lights.h"
#include "scene/loader.h"
#include "test_helpers.h"

using namespace rl;

namespace {

bool near(Vec3 a, Vec3 b, float eps = 1e-5f) { return length(a - b) <= eps; }

SpotLight make_spot(Vec3 position, Vec3 direction, Rgb intensity, float cone, float delta) {
  SpotLight l;
  l.position = position;
  l.direction = normalize(direction);
  l.intensity = intensity;
  l.cone_angle = cone;
  l.cone_delta = delta;
  return l;
}

// A floor quad (for the scene bounds), a spot 2 above the origin pointing down (cone 40, band 10),
// a distant light from direction (1, 2, 0) and a point light.
Scene delta_scene() {
  Scene s;
  s.materials.push_back({});
  TriangleMesh floor;
  floor.positions = {{-2, 0, -2}, {2, 0, -2}, {2, 0, 2}, {-2, 0, 2}};
  floor.indices = {0, 1, 2, 0, 2, 3};
  s.meshes.push_back(floor);
  s.spot_lights.push_back(make_spot({0, 2, 0}, {0, -1, 0}, Rgb(8, 6, 4), 40, 10));
  s.distant_lights.push_back({normalize(Vec3{1, 2, 0}), Rgb(1.5f, 1, 0.5f)});
  s.point_lights.push_back({{1, 3, 1}, Rgb(2)});
  return s;
}

float deg_cos(float degrees) { return std::cos(degrees * kPi / 180); }

std::string write_scene(const std::string& name, const std::string& world) {
  const std::filesystem::path dir = test::fresh_temp_dir(name);
  const std::string path = (dir / "s.pbrt").string();
  std::ofstream(path) << "LookAt 0 5 0  0 0 0  0 0 1\nCamera \"perspective\" \"float fov\" 40\nWorldBegin\n" << world;
  return path;
}

}  // namespace

TEST_SUITE("lights") {
  TEST_CASE("spot falloff: 1 inside the full cone, 0 outside, pbrt-v4's smoothstep in cos theta between") {
    const float c_end = deg_cos(40), c_start = deg_cos(30);
    CHECK(spot_falloff(1.0f, c_end, c_start) == 1.0f);
    CHECK(spot_falloff(c_start, c_end, c_start) == 1.0f);
    CHECK(spot_falloff(c_end, c_end, c_start) == 0.0f);
    CHECK(spot_falloff(deg_cos(60), c_end, c_start) == 0.0f);
    CHECK(spot_falloff(-1.0f, c_end, c_start) == 0.0f);
    const float mid = 0.5f * (c_end + c_start);  // t = 1/2: 3/4 - 2/8
    CHECK(spot_falloff(mid, c_end, c_start) == doctest::Approx(0.5f));
    const float t = 0.25f, c = c_end + t * (c_start - c_end);
    CHECK(spot_falloff(c, c_end, c_start) == doctest::Approx(t * t * (3 - 2 * t)).epsilon(1e-4));
    // conedeltaangle 0: a hard edge at the cone.
    CHECK(spot_falloff(deg_cos(39.9f), deg_cos(40), deg_cos(40)) == 1.0f);
    CHECK(spot_falloff(deg_cos(40.1f), deg_cos(40), deg_cos(40)) == 0.0f);
  }

  TEST_CASE("spot and distant emitters: kinds, pbrt-v4's powers, delta and at-infinity flags") {
    const Scene s = delta_scene();
    const Lights lights(s, LightSelection::power);
    REQUIRE(lights.emitter_count() == 3);
    const uint32_t point = 0, spot = 1, distant = 2;  // point lights, then spots, then distant lights
    CHECK(lights.kind(spot) == LightKind::spot);
    CHECK(lights.kind(distant) == LightKind::distant);
    for (uint32_t e : {point, spot, distant}) CHECK(lights.is_delta(e));
    CHECK(!lights.at_infinity(point));
    CHECK(!lights.at_infinity(spot));
    CHECK(lights.at_infinity(distant));
    const float cs = deg_cos(30), ce = deg_cos(40);
    CHECK(lights.power(spot) == doctest::Approx(luminance(Rgb(8, 6, 4)) * 2 * kPi * ((1 - cs) + (cs - ce) / 2)).epsilon(1e-5));
    const float r = 0.5f * length(s.bounds().diagonal());  // the floor's bounding sphere
    CHECK(lights.power(distant) == doctest::Approx(kPi * r * r * luminance(Rgb(1.5f, 1, 0.5f))).epsilon(1e-5));
    const double sum = lights.power(point) + lights.power(spot) + lights.power(distant);
    for (uint32_t e : {point, spot, distant}) CHECK(lights.selection_pmf(e) == doctest::Approx(lights.power(e) / sum).epsilon(1e-5));
  }

  TEST_CASE("spot sample_emitter: I falloff / d^2 toward the receiver, pdf 1, no sample outside the cone") {
    const Scene s = delta_scene();
    const Lights lights(s, LightSelection::uniform);
    const uint32_t spot = 1;
    LightSample ls;
    REQUIRE(lights.sample_emitter(spot, Vec3(0), Vec2(0.3f, 0.7f), ls));
    CHECK(ls.is_delta);
    CHECK(ls.pdf == 1.0f);
    CHECK(ls.distance == doctest::Approx(2));
    CHECK(near(ls.wi, {0, 1, 0}));
    CHECK(near(ls.position, {0, 2, 0}));
    CHECK(near(ls.radiance, Rgb(8, 6, 4) / 4.0f));
    // A receiver in the band (35 degrees off the axis): the smoothstep value.
    const float th = 35 * kPi / 180, x = 2 * std::tan(th);
    REQUIRE(lights.sample_emitter(spot, {x, 0, 0}, Vec2(0.5f, 0.5f), ls));
    const float d2 = x * x + 4, f = spot_falloff(std::cos(th), deg_cos(40), deg_cos(30));
    CHECK(f > 0.1f);
    CHECK(f < 0.9f);
    CHECK(ls.radiance.x == doctest::Approx(8 * f / d2).epsilon(1e-4));
    CHECK(lights.delta_emission(spot, ls.wi).y == doctest::Approx(6 * f).epsilon(1e-4));
    // Outside the cone (45 degrees) and behind the light: no sample, as for a black emitter.
    CHECK(!lights.sample_emitter(spot, {2, 0, 0}, Vec2(0.5f, 0.5f), ls));
    CHECK(!lights.sample_emitter(spot, {0, 3, 0}, Vec2(0.5f, 0.5f), ls));
    // Delta lights: no density for another strategy, counting measure for sample_point.
    CHECK(lights.pdf(spot, Vec3(0), {0, 2, 0}, Vec3(0)) == 0.0f);
    CHECK(lights.point_pdf(spot, {0, 2, 0}) == doctest::Approx(1.0f / 3));
    CHECK(is_black(lights.emitted(spot, {0, -1, 0}, {0, -1, 0})));
  }

  TEST_CASE("distant sample_emitter: L along the light's direction, unbounded, pdf 1, whatever the receiver") {
    const Scene s = delta_scene();
    const Lights lights(s, LightSelection::uniform);
    const uint32_t distant = 2;
    const Vec3 w = normalize(Vec3{1, 2, 0});
    for (Vec3 p : {Vec3(0), Vec3{5, -3, 2}, Vec3{-100, 7, 0}}) {
      LightSample ls;
      REQUIRE(lights.sample_emitter(distant, p, Vec2(0.9f, 0.1f), ls));
      CHECK(ls.is_delta);
      CHECK(ls.pdf == 1.0f);
      CHECK(ls.distance >= kInfinity);
      CHECK(near(ls.wi, w));
      CHECK(near(ls.position, w));
      CHECK(near(ls.radiance, Rgb(1.5f, 1, 0.5f)));
    }
    CHECK(lights.pdf(distant, Vec3(0), w, Vec3(0)) == 0.0f);
    CHECK(lights.point_pdf(distant, w) == doctest::Approx(1.0f / 3));
  }

  TEST_CASE("sample / sample_point of delta lights: frequencies follow the pmf, densities are the pmf") {
    const Scene s = delta_scene();
    const Lights lights(s, LightSelection::power);
    const int n = 30000;
    int count[3] = {0, 0, 0};
    Pcg32 rng(7, 3);
    for (int i = 0; i < n; ++i) {
      EmitterPoint ep;
      REQUIRE(lights.sample_point(rng.next_float(), rng.next_2d(), ep));
      REQUIRE(ep.emitter < 3);
      ++count[ep.emitter];
      CHECK(ep.pdf == doctest::Approx(lights.selection_pmf(ep.emitter)));
      CHECK(ep.pdf == doctest::Approx(lights.point_pdf(ep.emitter, ep.position)));
      CHECK(is_black(ep.normal));
      if (ep.emitter == 1) CHECK(near(ep.position, {0, 2, 0}));
      if (ep.emitter == 2) CHECK(near(ep.position, normalize(Vec3{1, 2, 0})));
    }
    for (uint32_t e = 0; e < 3; ++e) {  // binomial: within 5 standard deviations
      const double p = lights.selection_pmf(e), sd = std::sqrt(n * p * (1 - p));
      CHECK(std::fabs(count[e] - n * p) < 5 * sd);
    }
    // sample(): the pdf is the selection pmf, the radiance the emitter's.
    LightSample ls;
    int seen = 0;
    for (int i = 0; i < 200; ++i)
      if (lights.sample(Vec3{0.1f, 0, 0.2f}, rng.next_float(), rng.next_2d(), ls)) {
        ++seen;
        CHECK(ls.is_delta);
        CHECK(ls.pdf == doctest::Approx(lights.selection_pmf(ls.emitter)));
      }
    CHECK(seen == 200);  // the receiver is inside the spot's cone and faces every light
  }

  TEST_CASE("animated spot and distant lights: axis and direction turn, emission scales, follow() tracks them") {
    Scene rest = delta_scene();
    Animation a;
    a.keys = {AnimationKey{0, Vec3(0), 0, {0, 0, 1}, 1}, AnimationKey{1, Vec3{1, 0, 0}, 90, {0, 0, 1}, 0.5f}};
    rest.animations.push_back(a);
    rest.spot_lights[0].animation = 0;
    rest.distant_lights[0].animation = 0;
    CHECK(scene_animated(rest));
    CHECK(lights_animated(rest));
    Scene s0, s1;
    animate_scene(rest, 0, s0);
    animate_scene(rest, 1, s1);
    // Rotation by 90 degrees about +z through the origin, then +x: (0, 2, 0) -> (-2, 0, 0) + (1, 0, 0).
    CHECK(near(s1.spot_lights[0].position, {-1, 0, 0}));
    CHECK(near(s1.spot_lights[0].direction, {1, 0, 0}));
    CHECK(near(s1.spot_lights[0].intensity, Rgb(4, 3, 2)));
    CHECK(near(s1.distant_lights[0].direction, normalize(Vec3{-2, 1, 0})));  // turned, not translated
    CHECK(near(s1.distant_lights[0].radiance, Rgb(0.75f, 0.5f, 0.25f)));
    const Lights l0(s0, LightSelection::power), l1(s1, LightSelection::power);
    Vec3 pos{0, 2, 0}, n;
    REQUIRE(l1.follow(1, l0, pos, n));
    CHECK(near(pos, {-1, 0, 0}));
    pos = normalize(Vec3{1, 2, 0});
    REQUIRE(l1.follow(2, l0, pos, n));
    CHECK(near(pos, normalize(Vec3{-2, 1, 0})));
    const Scene frozen = scene_at_frame(rest, 1);
    CHECK(!scene_animated(frozen));
  }
}

TEST_SUITE("loaders") {
  TEST_CASE("pbrt: LightSource spot and distant -- defaults, from / to under the CTM, scale, illuminance") {
    const Scene s = load_scene(write_scene("delta-lights",
                                           "LightSource \"spot\"\n"
                                           "AttributeBegin\n  Translate 1 2 3\n  Rotate 90 1 0 0\n"
                                           "  LightSource \"spot\" \"rgb I\" [1 2 3] \"float scale\" 2 \"point3 from\" [0 0 0]\n"
                                           "    \"point3 to\" [0 1 0] \"float coneangle\" 50 \"float conedeltaangle\" 0\n"
                                           "  LightSource \"distant\" \"point3 from\" [0 0 0] \"point3 to\" [0 0 1] \"rgb L\" [1 1 2]\n"
                                           "AttributeEnd\n"
                                           "LightSource \"distant\" \"blackbody L\" 6500 \"float illuminance\" 3 \"float scale\" 2\n"));
    REQUIRE(s.spot_lights.size() == 2);
    REQUIRE(s.distant_lights.size() == 2);
    const SpotLight& d = s.spot_lights[0];  // pbrt-v4's defaults
    CHECK(near(d.position, Vec3(0)));
    CHECK(near(d.direction, {0, 0, 1}));
    CHECK(near(d.intensity, Rgb(1)));
    CHECK(d.cone_angle == 30);
    CHECK(d.cone_delta == 5);
    CHECK(d.cos_falloff_start() == doctest::Approx(deg_cos(25)));
    CHECK(d.cos_falloff_end() == doctest::Approx(deg_cos(30)));
    const SpotLight& t = s.spot_lights[1];  // Rotate 90 about x takes +y to +z
    CHECK(near(t.position, {1, 2, 3}));
    CHECK(near(t.direction, {0, 0, 1}));
    CHECK(near(t.intensity, Rgb(2, 4, 6)));
    CHECK(t.cone_angle == 50);
    CHECK(t.cone_delta == 0);
    CHECK(near(s.distant_lights[0].direction, {0, 1, 0}));  // toward the light: from - to = -z, rotated to +y
    CHECK(near(s.distant_lights[0].radiance, Rgb(1, 1, 2)));
    CHECK(near(s.distant_lights[1].direction, {0, 0, -1}));  // the defaults: from (0,0,0), to (0,0,1)
    CHECK(luminance(s.distant_lights[1].radiance) == doctest::Approx(6).epsilon(1e-3));  // blackbody: luminance 1, x 3 x 2
  }

  TEST_CASE("pbrt: a spot under a non-uniform scale is refused, and so is \"conedelta\" (pbrt-v4 reads conedeltaangle)") {
    CHECK_THROWS_WITH_AS(load_scene(write_scene("spot-scale", "Scale 1 2 1\nLightSource \"spot\"\n")),
                         doctest::Contains("uniform scale"), SceneError);
    CHECK_THROWS_WITH_AS(load_scene(write_scene("spot-delta", "LightSource \"spot\" \"float conedelta\" 3\n")),
                         doctest::Contains("\"float conedelta\": unused"), SceneError);
  }
}
