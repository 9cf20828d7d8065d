// OIDN (src/post/oidn.h) loaded at run time: a clear option error where the library is missing;
// where RESTIR_OIDN_LIBRARY names one (the pyoidn wheel's), the card scene at 1 and 16 spp denoised.
#include <doctest/doctest.h>

#include <cstdlib>
#include <string>

#include "denoise_scene.h"
#include "frame/render.h"
#include "image/metrics.h"
#include "test_helpers.h"

using namespace rl;
using namespace rl::test;

TEST_SUITE("oidn") {
  TEST_CASE("a missing OIDN library is an option error naming it and the way to give one") {
    const Scene scene = card_scene();
    const Options o = options_for(scene, {"denoise.method=oidn", "denoise.oidn_library=/nonexistent/libOpenImageDenoise.so.2"});
    CHECK_THROWS_WITH_AS(FrameRenderer(scene, o), doctest::Contains("cannot load '/nonexistent/libOpenImageDenoise.so.2'"), OptionError);
    CHECK_THROWS_WITH_AS(validate_options(options_for(scene, {"denoise.oidn_library=x.so"})),
                         doctest::Contains("read only by denoise.method = oidn"), OptionError);
  }

  TEST_CASE("oidn lowers the error of a 1 and a 16 spp render (skipped without RESTIR_OIDN_LIBRARY)") {
    const char* lib = std::getenv("RESTIR_OIDN_LIBRARY");
    if (!lib || !*lib) {
      MESSAGE("skipped: set RESTIR_OIDN_LIBRARY to an OIDN 2 libOpenImageDenoise.so (pip install pyoidn)");
      return;
    }
    const Scene scene = card_scene();
    Options ref = options_for(scene, {"render.spp=4096", "path.max_depth=1"});
    const Image reference = render(scene, ref).last;
    // 1 spp: far noisier than OIDN's output; 16 spp: closer to the reference, so a smaller factor.
    struct Case {
      const char* spp;
      double min_ratio;
    };
    for (const Case c : {Case{"render.spp=1", 5.0}, Case{"render.spp=16", 2.0}}) {
      CAPTURE(std::string(c.spp));
      const Options o = options_for(scene, {c.spp, "path.max_depth=1", "denoise.method=oidn"});
      const RenderResult r = render(scene, o);
      const double raw = rel_mse(r.last, reference), den = rel_mse(r.denoised, reference);
      MESSAGE(std::string(c.spp) << ": relMSE raw " << raw << ", oidn " << den << ": " << raw / den << "x lower");
      CHECK(raw / den >= c.min_ratio);
    }
  }
}
