// Replay compaction (pt.replay_compaction; ReSTIR PT Enhanced, sec. 6.2): paired reuse's pass 1
// makes the partners' shifts that replay a path prefix in a pass of their own, listed by
// Exec::select (frame/paired_reuse.h, reservoir_chain.h). It is a schedule, not an estimator: the
// same shifts write the same slots, so the frames must be the same images, bit for bit, on both
// host backends (cpu: Embree; cpu-bvh: the CUDA backend's host twin), with every shift mapping and
// with the RGB weights' per-shift colours. (A replay pass that skipped its list, measured while
// writing this test, changed 10-24% of the teapots' pixels per frame with the hybrid shift, 0.3-1%
// with RGB weights and two chains, and 69-71% of env-object's with random replay: the comparison
// sees a lost shift.) Which shifts are deferred is the bridge's needs_replay, checked per shift mapping.
#include <doctest/doctest.h>

#include <cstring>

#include "frame_loop.h"
#include "backends/cpu/embree_tracer.h"
#include "integrators/restir_pt/restir_pt_pixel.h"
#include "test_helpers.h"

using namespace rl;
using namespace rl::test;

namespace {

// The share of pixels whose bits differ between two frames (NaN compared by its bits too).
double differing(const Image& a, const Image& b) {
  if (a.size() != b.size()) return 1;
  size_t n = 0;
  for (size_t i = 0; i < a.size(); ++i) n += std::memcmp(&a.pixels[i], &b.pixels[i], sizeof(a.pixels[i])) != 0;
  return double(n) / double(a.size());
}

void check_same_frames(const std::string& scene_name, std::vector<const char*> sets, Backend backend) {
  CAPTURE(scene_name);
  CAPTURE(int(backend));
  const Scene scene = load_scene(own_scene(scene_name));
  Options o = options_for(scene, {"integrator=restir-pt", "film.width=48", "film.height=32", "pt.spatial_pairing=paired"});
  for (const char* s : sets) set_option_assignment(o, s);
  o.render.backend = backend;
  const std::vector<Image> plain = render_frames(scene, o, &make_registered, 3);
  set_option(o, "pt.replay_compaction", "true");
  const std::vector<Image> compacted = render_frames(scene, o, &make_registered, 3);
  double mean = 0;
  for (const auto& px : plain.back().pixels) mean += luminance(px);
  CHECK(mean > 0);  // a lit image: equality of black frames would prove nothing
  for (size_t f = 0; f < plain.size(); ++f) {
    const double d = differing(plain[f], compacted[f]);
    INFO("frame " << f << ": " << d * 100 << "% of pixels differ");
    CHECK(d == 0);
  }
}

}  // namespace

TEST_SUITE("restir_pt") {
  TEST_CASE("replay compaction: the same frames, bit for bit, on both host backends and every shift mapping") {
    for (Backend backend : {Backend::cpu, Backend::cpu_bvh}) {
      check_same_frames("teapot.pbrt", {}, backend);                                       // hybrid: prefixes and reconnections
      check_same_frames("teapot.pbrt", {"pt.rgb_weights=true", "render.spp=2"}, backend);  // per-shift colours, two chains
      check_same_frames("env-object.pbrt", {"pt.shift=random-replay", "path.russian_roulette=true"}, backend);  // every shift replays
      check_same_frames("teapot.pbrt", {"pt.shift=reconnection", "pt.spatial_rounds=2"}, backend);  // nothing deferred; two rounds
    }
  }

  TEST_CASE("replay compaction defers exactly the shifts that trace from the offset primary hit") {
    PtBridges<EmbreeTracer> bridges{};
    const PtBridge<EmbreeTracer> bridge{&bridges, SurfaceList{}, false, false, nullptr};
    PathSample y;
    y.length = 4;
    for (int rc : {0, 2, 3, 4}) {
      CAPTURE(rc);
      y.rc = uint8_t(rc);
      bridges.ps.pt.shift = ShiftMapping::hybrid;
      CHECK(bridge.needs_replay(y) == (rc != 2));  // x_2 reconnects straight from the primary hit
      bridges.ps.pt.shift = ShiftMapping::random_replay;
      CHECK(bridge.needs_replay(y));
      bridges.ps.pt.shift = ShiftMapping::reconnection;
      CHECK_FALSE(bridge.needs_replay(y));
    }
    CHECK_FALSE(bridges.compact_replays());
    bridges.ps.pt.replay_compaction = true;
    CHECK(bridges.compact_replays());
  }

  TEST_CASE("replay compaction needs paired reuse") {
    Options o;
    o.integrator = "restir-pt";
    set_option(o, "pt.replay_compaction", "true");
    CHECK_THROWS_WITH_AS(validate_options(o), doctest::Contains("needs pt.spatial_pairing = paired"), OptionError);
    set_option(o, "pt.spatial_pairing", "paired");
    CHECK_NOTHROW(validate_options(o));
  }
}
