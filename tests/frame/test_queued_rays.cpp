// The reuse passes' shadow rays as producer -> trace -> consumer (render.reuse_rays = queued,
// frame/ray_slots.h; issue 48): the queued pass renders the inline pass's image bit for bit, on the
// CUDA backend's host twin (cpu-bvh: the code the GPU runs) and on the CPU backend, and -- with the
// MIS weights whose queries follow from the inputs (pairwise, generalized balance) -- every any-hit
// query of the pass is answered from the queue, and no queued ray is traced in vain.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "frame/ray_slots.h"
#include "frame/render.h"
#include "scene/loader.h"
#include "test_helpers.h"

using namespace rl;
using namespace rl::test;

namespace {

struct Rendered {
  std::vector<StageTimes> frames;
  Image last;
};

Rendered render_frames(const Scene& scene, const Options& o, int frames) {
  FrameRenderer renderer(scene, o);
  const CameraKey key = scene.camera.keys.empty() ? CameraKey{} : scene.camera.keys.front();
  Rendered r;
  for (int f = 0; f < frames; ++f) {
    Image img(o.film.width, o.film.height);
    StageTimes st;
    renderer.render_frame(key, frames, img, &st);
    r.frames.push_back(std::move(st));
    r.last = std::move(img);
  }
  return r;
}

struct Case {
  std::string scene, integrator;
  std::vector<const char*> sets;
  bool all_queued;  // every any-hit query of the reuse passes comes from the queue
};

// Each integrator at its defaults; each MIS kind (1/Z's last loop reads the selected sample: a few
// queries the producer cannot predict, traced inline); generalized balance with more neighbours
// than the slots hold (the overflow, traced inline); an animated scene whose history is judged in
// the previous frame's BVH (traced inline: the queue holds this frame's rays); paired reuse (not
// queued: its passes keep their own schedule) beside a queued temporal pass.
const std::vector<Case> kCases = {
    {"many-lights.pbrt", "restir-di", {}, true},
    {"many-lights.pbrt", "restir-di", {"di.spatial_mis=one-over-z", "di.temporal_mis=one-over-z"}, false},
    {"many-lights.pbrt", "restir-di", {"di.spatial_mis=generalized-balance", "di.spatial_neighbors=12"}, true},
    {"stripes.pbrt", "restir-di", {"di.spatial_pairing=paired"}, true},
    {"cornell-box.pbrt", "restir-gi", {}, true},
    {"teapot.pbrt", "restir-gi", {"gi.spatial_rounds=2"}, true},
    {"cornell-box.pbrt", "restir-gi", {"render.debug_view=rejected-shifts"}, true},  // the producer leaves the counters as it found them
    {"cornell-box.pbrt", "restir-di", {"render.debug_view=reuse-source"}, true},
    {"cornell-box.pbrt", "restir-pt", {"path.max_depth=4"}, true},
    {"stripes.pbrt", "restir-pt", {"path.max_depth=4", "pt.shift=reconnection", "pt.spatial_mis=symmetric-ratio"}, true},
    {"cornell-box.pbrt", "restir-pt", {"path.max_depth=3", "pt.spatial_mis=generalized-balance", "pt.spatial_radius=6", "pt.spatial_neighbors=16"}, false},
    {"dynamic-room.pbrt", "restir-pt", {"path.max_depth=3", "pt.shift=random-replay"}, false},
};

bool same_bits(const Image& a, const Image& b) {
  return a.width == b.width && a.height == b.height && !a.empty() &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(a.pixels[0])) == 0;
}

// A tracer that answers "occluded" for rays whose tmax is 2 and counts its queries.
struct FakeTracer {
  mutable int any = 0;
  bool occluded(const Ray& r) const {
    ++any;
    return r.tmax == 2.0f;
  }
};

Ray ray(float ox, float tmax) { return Ray{Vec3(ox, 0, 0), Vec3(0, 0, 1), 0.0f, tmax}; }

}  // namespace

TEST_SUITE("queued_rays") {
  TEST_CASE("a pixel's cursor: the producer records and counts, the consumer answers recorded rays and traces the others") {
    std::vector<Ray> rays(2 * 3);
    std::vector<uint8_t> answers(2 * 3, 0);
    std::vector<uint32_t> counts(2, 0);
    const RaySlotsView slots{rays.data(), answers.data(), counts.data(), 3};
    FakeTracer tracer;
    RayCursor producer{slots, 1, true};
    for (float ox : {0.0f, 1.0f, 2.0f, 3.0f}) CHECK_FALSE(producer.occluded(tracer, ray(ox, ox == 1.0f ? 2.0f : 1.0f)));
    producer.finish();
    CHECK(tracer.any == 0);         // the producer traces nothing
    CHECK(counts[1] == 4);          // four queries, three recorded
    CHECK(counts[0] == 0);          // pixel 0 untouched
    CHECK(rays[3 + 1].o.x == 1.0f);  // pixel 1's slot 1
    // The trace stage, over the recorded slots only.
    std::vector<uint32_t> list;
    for (size_t s = 0; s < rays.size(); ++s)
      if (RecordedSlot{slots}(s)) list.push_back(uint32_t(s));
    CHECK(list == std::vector<uint32_t>{3, 4, 5});
    for (uint32_t s : list) answers[s] = tracer.occluded(rays[s]) ? 1 : 0;
    CHECK(tracer.any == 3);
    RayCursor consumer{slots, 1, false};
    CHECK(consumer.occluded(tracer, ray(1, 2)));        // slot 1's ray, asked first: occluded, from the queue
    CHECK_FALSE(consumer.occluded(tracer, ray(0, 1)));  // slot 0's: from the queue
    CHECK(tracer.any == 3);
    CHECK(consumer.occluded(tracer, ray(7, 2)));  // slot 2 holds another ray: traced
    CHECK(tracer.any == 4);
    CHECK(consumer.occluded(tracer, ray(3, 2)));  // past the slots: traced
    CHECK(tracer.any == 5);
    // A ray that differs from the recorded one in its last bit only is not the recorded ray.
    answers[3] = 1;  // a queue that would (wrongly) say slot 0 is occluded
    RayCursor again{slots, 1, false};
    Ray nudged = ray(0, 1);
    nudged.tmax = std::nextafter(1.0f, 2.0f);
    CHECK_FALSE(again.occluded(tracer, nudged));
    CHECK(tracer.any == 6);
  }

  TEST_CASE("slots per pixel: two per neighbour (one for generalized balance's n(n-1)), capped") {
    CHECK(ray_slots_per_pixel(restir::ReuseMis::pairwise, 6) == 11);
    CHECK(ray_slots_per_pixel(restir::ReuseMis::generalized_balance, 2) == 3);
    CHECK(ray_slots_per_pixel(restir::ReuseMis::generalized_balance, 13) == kMaxRaySlots);
    CHECK(ray_slots_per_pixel(restir::ReuseMis::pairwise, 1) == 1);
  }

  TEST_CASE("a queued reuse pass renders the inline pass's image bit for bit, every shadow ray from its queue") {
    for (const Case& c : kCases) {
      for (const std::string backend : {"render.backend=cpu-bvh", "render.backend=cpu"}) {
        CAPTURE(c.scene);
        CAPTURE(c.integrator);
        CAPTURE(backend);
        const std::string sets = c.sets.empty() ? "" : c.sets.back();
        CAPTURE(sets);
        const Scene scene = load_scene(own_scene(c.scene));
        Options o = options_for(scene, {"render.spp=1", backend.c_str()});
        for (const char* s : c.sets) set_option_assignment(o, s);
        o.integrator = c.integrator;
        o.film.width = 40, o.film.height = 24;
        const Rendered inline_pass = render_frames(scene, o, 3);
        set_option_assignment(o, "render.reuse_rays=queued");
        const Rendered queued = render_frames(scene, o, 3);
        CHECK(same_bits(inline_pass.last, queued.last));
        for (size_t f = 0; f < queued.frames.size(); ++f) {
          CAPTURE(f);
          for (const std::string stage : {"temporal", "spatial"}) {
            CAPTURE(stage);
            const RayCounts a = inline_pass.frames[f].rays_of(stage), b = queued.frames[f].rays_of(stage);
            CHECK(a.queued == 0);
            // No queued ray traced in vain, none traced twice. (Elsewhere either way: a ray the
            // pass asks twice is traced once from the queue, one the producer asked in vain is not
            // asked again.)
            if (c.all_queued) CHECK(b.any == a.any);
            CHECK(b.closest >= a.closest);      // the producer replays what the pass replays
            CHECK(b.queued <= b.any);
            const bool paired_spatial = stage == "spatial" && c.sets.size() > 0 &&
                                        std::string(c.sets[0]).find("spatial_pairing=paired") != std::string::npos;
            if (paired_spatial) {
              CHECK(b.queued == 0);
            } else if (c.all_queued) {
              CHECK(b.queued == b.any);
            }
          }
        }
        RayCounts reuse;  // the reuse passes' rays over the frames
        for (const StageTimes& st : queued.frames) reuse += st.rays_of("temporal") + st.rays_of("spatial");
        CHECK(reuse.queued > 0);
        if (!c.all_queued) CHECK(reuse.queued < reuse.any);  // some traced inline: the fallback ran
      }
    }
  }
}
