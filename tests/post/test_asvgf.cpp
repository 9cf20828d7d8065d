// A-SVGF (src/post/asvgf.h, Schied et al. 2018) on the card scene (tests/support/denoise_scene.h):
// where nothing changes the re-shaded samples equal the old ones and it is SVGF bit for bit; when a
// light switches off it drops the history within 2 frames, where SVGF still shows the old light.
#include <doctest/doctest.h>

#include "denoise_scene.h"
#include "frame/render.h"
#include "image/metrics.h"
#include "post/asvgf.h"
#include "test_helpers.h"

using namespace rl;
using namespace rl::test;

namespace {

Options card_options(const char* method, const char* spp = "render.spp=1") {
  Options o = options_for(card_scene(), {spp, "path.max_depth=1"});
  set_option(o, "denoise.method", method);
  return o;
}

double mean_luminance(const Image& img) {
  double s = 0;
  for (const Rgb& p : img.pixels) s += luminance(p);
  return s / double(img.size());
}

// The denoised frames 0..frames-1 of the card scene with `light`, still camera.
std::vector<Image> denoised_frames(CardLight light, const char* method, int frames) {
  const Scene scene = card_scene(light);
  FrameRenderer r(scene, card_options(method));
  std::vector<Image> out;
  Image raw;
  for (int f = 0; f < frames; ++f) {
    r.render_frame(card_camera(0), frames, raw, nullptr);
    out.push_back(r.denoised());
  }
  return out;
}

}  // namespace

TEST_SUITE("asvgf") {
  TEST_CASE("a-svgf is svgf where nothing changes: the re-shaded samples are the old ones") {
    const auto a = denoised_frames(CardLight::steady, "asvgf", 5), s = denoised_frames(CardLight::steady, "svgf", 5);
    for (size_t f = 0; f < a.size(); ++f) CHECK(a[f].pixels == s[f].pixels);
  }

  TEST_CASE("after a light switches off, a-svgf drops the history within 2 frames where svgf lags") {
    // The light is on for frames 0-5 and off from frame 6; the reference is the scene without it.
    const Image off = render(card_scene(CardLight::off), card_options("none", "render.spp=1024")).last;
    const auto a = denoised_frames(CardLight::blink, "asvgf", 8), s = denoised_frames(CardLight::blink, "svgf", 8);
    const double ref = mean_luminance(off), on = mean_luminance(a[5]);
    // What remains of the old light 2 frames after the switch: (mean - off) / (on - off).
    const double ar = (mean_luminance(a[7]) - ref) / (on - ref), sr = (mean_luminance(s[7]) - ref) / (on - ref);
    MESSAGE("mean luminance: light on " << on << ", off (reference) " << ref << "; 2 frames after the switch: a-svgf "
            << mean_luminance(a[7]) << " (" << 100 * ar << "% of the old light left), svgf " << mean_luminance(s[7]) << " ("
            << 100 * sr << "% left)");
    MESSAGE("relMSE 2 frames after the switch: a-svgf " << rel_mse(a[7], off) << ", svgf " << rel_mse(s[7], off));
    CHECK(on > 4 * ref);  // the switch is a large change
    // Eq. 8's lambda = |delta| / max(l_old, l_new) is 0.88 here, not 1: a-svgf keeps 12% of the old
    // history at the switch (alpha 0.9), and alpha falls back to 0.2 the frame after.
    CHECK(ar < 0.1);
    CHECK(sr > 0.5);  // svgf: (1 - alpha)^2 = 64% of the old light
  }

  TEST_CASE("a-svgf needs an integrator that re-shades the previous frame's samples") {
    const Scene scene = card_scene();
    Options o = options_for(scene, {"integrator=restir-di", "denoise.method=asvgf"});
    CHECK_THROWS_WITH_AS(FrameRenderer(scene, o), doctest::Contains("re-shades"), OptionError);
  }
}
