// SVGF's per-pixel stages (src/post/svgf_driver.h) on the host execution policy against the CPU's
// vectorised Svgf (svgf.cpp): the same frames and AOVs in, the same floats out, frame after frame
// (svgf_stages.h holds the math both call). A parameter changed by one ulp on one side shows in the
// output (the equality has power); the stages give the same bits on 1 and 2 threads; make_denoiser
// hands each backend its SVGF, and A-SVGF wraps the one its backend gets.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <functional>

#include "backends/cpu/host_exec.h"
#include "denoise_scene.h"
#include "denoiser_frames.h"
#include "frame/render.h"
#include "post/asvgf.h"
#include "post/svgf.h"
#include "post/svgf_driver.h"
#include "test_helpers.h"

using namespace rl;
using namespace rl::test;

namespace {

using Input = DenoiserInput;

// The card scene at 1 spp, the camera moving right in uneven steps (sub-pixel and several-pixel
// shifts, a disocclusion behind the card's edge) after two still frames.
const std::vector<Input>& card_frames() {
  static const std::vector<Input> frames = [] {
    const Scene scene = card_scene();
    const float dx[] = {0, 0, 0.05f, 0.3f, 0.5f, 0.55f, 0.55f, 0.9f};
    return render_denoiser_inputs(scene, options_for(scene, {"render.spp=1", "path.max_depth=2"}), 8,
                         [&](int f) { return card_camera(dx[f]); });
  }();
  return frames;
}

// ReSTIR DI on the Cornell box, the camera along its path (scenes/cornell-box.camera.json).
const std::vector<Input>& restir_di_frames() {
  static const std::vector<Input> frames = [] {
    Scene scene = load_scene(own_scene("cornell-box.pbrt"));
    load_camera_path(own_scene("cornell-box.camera.json"), scene.camera);
    const Options o = options_for(scene, {"integrator=restir-di", "film.width=80", "film.height=60", "render.spp=1"});
    return render_denoiser_inputs(scene, o, 6, [&](int f) { return scene.camera.at_frame(f, 6); });
  }();
  return frames;
}

DenoiseOptions svgf_options(std::initializer_list<std::pair<float DenoiseOptions::*, float>> sets = {}) {
  DenoiseOptions d;
  d.method = DenoiseMethod::svgf;
  for (const auto& [field, value] : sets) d.*field = value;
  return d;
}

// The frames through a and b: the differing floats of each frame's output and history lengths.
struct Differences {
  std::vector<size_t> image, history;
  size_t floats() const {
    size_t n = 0;
    for (size_t x : image) n += x;
    return n;
  }
  size_t total() const {
    size_t n = floats();
    for (size_t x : history) n += x;
    return n;
  }
};
Differences compare(SvgfFilter& a, SvgfFilter& b, const std::vector<Input>& frames) {
  Differences d;
  Image oa, ob;
  for (const Input& f : frames) {
    a.denoise(f.raw, f.aovs, oa);
    b.denoise(f.raw, f.aovs, ob);
    d.image.push_back(differing_floats(oa, ob));
    const std::vector<float>& ha = a.history_length();
    const std::vector<float>& hb = b.history_length();
    REQUIRE(ha.size() == hb.size());
    d.history.push_back(size_t(std::memcmp(ha.data(), hb.data(), ha.size() * sizeof(float)) != 0));
  }
  return d;
}

std::string join(const std::vector<size_t>& v) {
  std::string s;
  for (size_t x : v) s += (s.empty() ? "" : " ") + std::to_string(x);
  return s;
}

}  // namespace

TEST_SUITE("svgf_stages") {
  TEST_CASE("the stages on the host give Svgf's floats: card scene under camera motion, ReSTIR DI, sigma_n not a power of 2") {
    struct Setup {
      const char* name;
      const std::vector<Input>& frames;
      DenoiseOptions o;
      int iterations = 5;
    };
    const Setup setups[] = {
        {"card scene, camera moving, defaults", card_frames(), svgf_options()},
        {"card scene, sigma_n 100 (std::pow), sigma_z 0.5, sigma_l 2, 3 iterations", card_frames(),
         svgf_options({{&DenoiseOptions::sigma_n, 100.0f}, {&DenoiseOptions::sigma_z, 0.5f}, {&DenoiseOptions::sigma_l, 2.0f}}), 3},
        {"cornell box, restir-di, camera path, defaults", restir_di_frames(), svgf_options()},
        {"cornell box, restir-di, alpha 0.05, moments alpha 0.5, sigma_n 1", restir_di_frames(),
         svgf_options({{&DenoiseOptions::alpha, 0.05f}, {&DenoiseOptions::moments_alpha, 0.5f}, {&DenoiseOptions::sigma_n, 1.0f}})},
    };
    for (const Setup& s : setups) {
      const std::string name = s.name;
      CAPTURE(name);
      DenoiseOptions o = s.o;
      o.atrous_iterations = s.iterations;
      Svgf fast(o);
      SvgfStages<HostExec> stages(o);
      const Differences d = compare(fast, stages, s.frames);
      MESSAGE(name << ": " << s.frames.size() << " frames of " << 3 * s.frames[0].raw.size()
                     << " floats; differing floats by frame: " << join(d.image)
                     << "; history lengths differ in frames: " << join(d.history));
      CHECK(d.total() == 0);
    }
  }

  TEST_CASE("a parameter one ulp off on one side is detected: the equality has power") {
    using P = float DenoiseOptions::*;
    const std::pair<const char*, P> params[] = {{"sigma_l", &DenoiseOptions::sigma_l},
                                                {"sigma_z", &DenoiseOptions::sigma_z},
                                                {"alpha", &DenoiseOptions::alpha},
                                                {"moments_alpha", &DenoiseOptions::moments_alpha}};
    for (const auto& [param, field] : params) {
      const std::string name = param;
      CAPTURE(name);
      const DenoiseOptions o = svgf_options();
      DenoiseOptions planted = o;
      planted.*field = std::nextafter(o.*field, 2 * o.*field);  // one ulp up
      REQUIRE(planted.*field != o.*field);
      size_t card = 0, di = 0;
      {
        Svgf fast(o);
        SvgfStages<HostExec> stages(planted);
        card = compare(fast, stages, card_frames()).floats();
      }
      {
        Svgf fast(o);
        SvgfStages<HostExec> stages(planted);
        di = compare(fast, stages, restir_di_frames()).floats();
      }
      MESSAGE(name << " one ulp up on the stages' side: " << card << " differing floats (card scene, 8 frames), " << di
                   << " (restir-di, 6 frames)");
      CHECK(card > 0);
      CHECK(di > 0);
    }
  }

  TEST_CASE("a-svgf over the stages equals a-svgf over Svgf (lambda from a light that switches off)") {
    const Scene scene = card_scene(CardLight::blink);
    Options o = options_for(scene, {"render.spp=1", "path.max_depth=1", "denoise.method=asvgf"});
    const std::vector<Input> frames = render_denoiser_inputs(scene, o, 9, [](int) { return card_camera(0); });
    Asvgf fast(o.denoise), stages(o.denoise, std::make_unique<SvgfStages<HostExec>>(o.denoise));
    size_t differing = 0, lambda_frames = 0;
    Image a, b;
    for (const Input& f : frames) {
      if (!f.reshaded.empty()) fast.set_reshaded_previous(f.reshaded), stages.set_reshaded_previous(f.reshaded);
      fast.denoise(f.raw, f.aovs, a);
      stages.denoise(f.raw, f.aovs, b);
      differing += differing_floats(a, b);
      bool any = false;
      for (float l : fast.lambda()) any = any || l > 0.5f;
      lambda_frames += any;
    }
    MESSAGE("a-svgf, 9 frames: " << differing << " differing floats; frames with some lambda > 0.5: " << lambda_frames);
    CHECK(lambda_frames > 0);  // the gradient path ran
    CHECK(differing == 0);
  }

  TEST_CASE("make_denoiser: cpu gets Svgf, cpu-bvh the stages on the host; a-svgf wraps the backend's") {
    Options o;
    set_option(o, "denoise.method", "svgf");
    CHECK(dynamic_cast<Svgf*>(make_denoiser(o).get()) != nullptr);
    set_option(o, "render.backend", "cpu-bvh");
    CHECK(dynamic_cast<SvgfStages<HostExec>*>(make_denoiser(o).get()) != nullptr);
    set_option(o, "denoise.method", "asvgf");
    const auto d = make_denoiser(o);
    const auto* a = dynamic_cast<Asvgf*>(d.get());
    REQUIRE(a != nullptr);
    CHECK(dynamic_cast<const SvgfStages<HostExec>*>(&a->svgf()) != nullptr);
    set_option(o, "render.backend", "cpu");
    const auto c = make_denoiser(o);
    CHECK(dynamic_cast<const Svgf*>(&dynamic_cast<Asvgf&>(*c).svgf()) != nullptr);
  }

  TEST_CASE("the stages give the same bits on 1 and 2 threads (render.backend = cpu-bvh)") {
    const Scene scene = load_scene(own_scene("cornell-box.pbrt"));
    Image first;
    for (const char* threads : {"render.threads=1", "render.threads=2"}) {
      const Options o = options_for(scene, {"film.width=48", "film.height=40", "render.spp=1", "render.frames=4", "render.backend=cpu-bvh",
                                            "denoise.method=svgf", threads});
      const RenderResult res = render(scene, o);
      REQUIRE(res.denoised.width == 48);
      CHECK(res.last.pixels != res.denoised.pixels);  // it filtered
      if (first.empty()) first = res.denoised;
      else CHECK(differing_floats(res.denoised, first) == 0);
    }
  }
}
