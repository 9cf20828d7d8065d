// Ray counters per stage (issue 48: measure before redesigning; core/ray_counter.h): the per-pixel
// stages count through their tracer, the queues (primary hits, a wavefront's trace_closest /
// trace_any) on the host, and StageTimer attributes the difference to its stage. Checked against
// the CPU backend's own log of every query Embree answered, across thread counts, with counting on
// and off, and between the CPU backend and the CUDA backend's host twin (cpu-bvh), whose
// per-pixel tracer counts through the same slots the device uses.
#include <doctest/doctest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "backends/cpu/accel.h"
#include "frame/render.h"
#include "scene/loader.h"
#include "test_helpers.h"

using namespace rl;
using namespace rl::test;

namespace doctest {
template <>
struct StringMaker<RayCounts> {
  static String convert(const RayCounts& c) { return ("{closest " + std::to_string(c.closest) + ", any " + std::to_string(c.any) + "}").c_str(); }
};
}  // namespace doctest

namespace {

struct Counted {
  std::vector<StageTimes> frames;
  Image last;
};

// `frames` frames through FrameRenderer (the scene's first camera key), each frame's stage times
// and rays recorded unless `record` is false; every query Embree answers goes to `log` when given.
Counted render_counted(const Scene& scene, const Options& o, int frames, RayLog* log = nullptr, bool record = true) {
  FrameRenderer renderer(scene, o);
  if (log) renderer.set_ray_log(log);
  const CameraKey key = scene.camera.keys.empty() ? CameraKey{} : scene.camera.keys.front();
  Counted c;
  for (int f = 0; f < frames; ++f) {
    Image img(o.film.width, o.film.height);
    StageTimes st;
    renderer.render_frame(key, frames, img, record ? &st : nullptr);
    c.frames.push_back(std::move(st));
    c.last = std::move(img);
  }
  renderer.set_ray_log(nullptr);
  return c;
}

Options small(const Scene& scene, const std::string& integrator, const std::vector<const char*>& sets, int w = 32, int h = 24) {
  Options o = options_for(scene, {"render.spp=1"});  // the scenes ask for up to 64 (chains, for ReSTIR)
  for (const char* s : sets) set_option_assignment(o, s);
  o.integrator = integrator;
  o.film.width = w, o.film.height = h;
  return o;
}

struct Case {
  std::string scene, integrator;
  std::vector<const char*> sets;
};

// The ReSTIR integrators and the path tracer in the configurations that trace differently: each
// shift, pt.direct = restir-di (a nested DI frame), paired reuse, visibility reuse off.
const std::vector<Case> kCases = {
    {"cornell-box.pbrt", "pt", {"path.max_depth=4"}},
    {"many-lights.pbrt", "restir-di", {}},
    {"many-lights.pbrt", "restir-di", {"di.visibility_reuse=false", "di.spatial_pairing=paired"}},
    {"cornell-box.pbrt", "restir-gi", {}},
    {"cornell-box.pbrt", "restir-pt", {"path.max_depth=4"}},
    {"cornell-box.pbrt", "restir-pt", {"path.max_depth=4", "pt.shift=random-replay", "pt.spatial_pairing=paired"}},
    {"cornell-box.pbrt", "restir-pt", {"path.max_depth=4", "pt.direct=restir-di"}},
    {"mirror-floor.pbrt", "ssr", {"ssr.temporal=true"}},
};

}  // namespace

TEST_SUITE("ray_counts") {
  TEST_CASE("a frame's counted rays are every query Embree answered, by kind, and each stage has its own") {
    for (const Case& c : kCases) {
      CAPTURE(c.scene);
      CAPTURE(c.integrator);
      const Scene scene = load_scene(own_scene(c.scene));
      const Options o = small(scene, c.integrator, c.sets);
      RayLog log;
      const Counted r = render_counted(scene, o, 3, &log);
      RayCounts counted;
      for (const StageTimes& st : r.frames) counted += st.total_rays();
      CHECK(counted.closest == log.closest().size());
      CHECK(counted.any == log.any_hit().size());
      CHECK(counted.any > 0);
      const uint64_t pixels = uint64_t(o.film.width) * uint64_t(o.film.height);
      for (const StageTimes& st : r.frames) {
        for (const auto& [name, rays] : st.rays) CHECK(st.of(name) > 0);  // every counted stage was timed
        if (c.integrator == "ssr") {
          CHECK(st.rays_of("primary") == RayCounts{pixels, 0});  // the camera rays, one queue
          CHECK(st.rays_of("direct").total() > 0);                // the lit colour: the path tracer at depth 1
          CHECK(st.rays_of("reflections").total() == 0);          // marched through the screen: no ray
        } else if (c.integrator == "pt") {
          CHECK(st.rays_of("camera").total() == 0);  // the camera stage makes rays, "intersect" traces them
          CHECK(st.rays_of("intersect").closest >= pixels);
          CHECK(st.rays_of("shadow").any > 0);
        } else {
          CHECK(st.rays_of("primary") == RayCounts{pixels, 0});  // one camera ray a pixel
          CHECK(st.rays_of("candidates").total() > 0);
          if (c.sets.empty() || std::string(c.sets[0]) != "di.visibility_reuse=false")  // V in the targets: shadow rays
            CHECK(st.rays_of("spatial").total() > 0);
        }
      }
      CHECK(r.frames[0].rays_of("temporal").total() == 0);  // no history yet
      if (c.sets.size() > 1 && std::string(c.sets[1]) == "pt.direct=restir-di")
        CHECK(r.frames[1].rays_of("di.primary") == RayCounts{pixels, 0});  // the nested DI frame's, under di.
    }
  }

  TEST_CASE("counting changes no pixel, and the counts do not depend on the thread count") {
    for (const char* backend : {"cpu", "cpu-bvh"})
      for (const Case& c : {kCases[2], kCases[5]}) {
        CAPTURE(backend);
        CAPTURE(c.integrator);
        const Scene scene = load_scene(own_scene(c.scene));
        Options o = small(scene, c.integrator, c.sets);
        set_option(o, "render.backend", backend);
        set_option(o, "render.threads", "1");
        const Counted one = render_counted(scene, o, 3);
        set_option(o, "render.threads", "3");
        const Counted three = render_counted(scene, o, 3), unrecorded = render_counted(scene, o, 3, nullptr, false);
        CHECK(one.last.pixels == three.last.pixels);
        CHECK(three.last.pixels == unrecorded.last.pixels);
        for (size_t f = 0; f < 3; ++f) CHECK(one.frames[f].rays == three.frames[f].rays);
        CHECK(unrecorded.frames[2].rays.empty());
      }
  }

  // The host twin runs the GPU's frames with its slots (the device's counter, with host atomics):
  // same stages, same rays but where Embree's and the BVH's rounding tip a path (test_backends.cpp).
  TEST_CASE("the CUDA backend's host twin counts the same rays per stage as the CPU backend, animated scenes too") {
    std::vector<Case> cases = kCases;
    cases.push_back({"dynamic-room.pbrt", "restir-pt", {"path.max_depth=3", "pt.shift=random-replay"}});  // the previous frame's tracer counts too
    cases.push_back({"dynamic-room.pbrt", "restir-di", {}});
    for (const Case& c : cases) {
      CAPTURE(c.scene);
      CAPTURE(c.integrator);
      const Scene scene = load_scene(own_scene(c.scene));
      Options o = small(scene, c.integrator, c.sets);
      const Counted cpu = render_counted(scene, o, 3);
      set_option(o, "render.backend", "cpu-bvh");
      const Counted twin = render_counted(scene, o, 3);
      for (size_t f = 0; f < 3; ++f)
        for (const auto& [name, rays] : cpu.frames[f].rays) {
          CAPTURE(f);
          CAPTURE(name);
          const RayCounts t = twin.frames[f].rays_of(name);
          CHECK(double(t.closest) == doctest::Approx(double(rays.closest)).epsilon(0.01));
          CHECK(double(t.any) == doctest::Approx(double(rays.any)).epsilon(0.01));
        }
    }
  }
}
