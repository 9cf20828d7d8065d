// OIDN (src/post/oidn.h) loaded at run time: a clear option error where the library is missing;
// where RESTIR_OIDN_LIBRARY names one (the pyoidn wheel's), the card scene at 1 spp denoised.
#include <doctest/doctest.h>

#include <cstdlib>

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

  TEST_CASE("oidn lowers the error of a 1 spp render (skipped without RESTIR_OIDN_LIBRARY)") {
    const char* lib = std::getenv("RESTIR_OIDN_LIBRARY");
    if (!lib || !*lib) {
      MESSAGE("skipped: set RESTIR_OIDN_LIBRARY to an OIDN 2 libOpenImageDenoise.so (pip install pyoidn)");
      return;
    }
    const Scene scene = card_scene();
    const Options o = options_for(scene, {"render.spp=1", "path.max_depth=1", "denoise.method=oidn"});
    const RenderResult r = render(scene, o);
    Options ref = options_for(scene, {"render.spp=2048", "path.max_depth=1"});
    const Image reference = render(scene, ref).last;
    const double raw = rel_mse(r.last, reference), den = rel_mse(r.denoised, reference);
    MESSAGE("relMSE raw " << raw << ", oidn " << den << ": " << raw / den << "x lower");
    CHECK(raw / den >= 5);
  }
}
