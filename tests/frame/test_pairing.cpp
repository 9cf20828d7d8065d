// Pairing textures of paired spatial reuse (frame/pairing.h; Lin, Kettunen, Wyman 2026, sec. 3):
// the partner relation must be an involution on every pixel of every frame, spatial round, chain
// and seed (a pixel reads its partner's shift of its own sample, which is only right if the partner
// is paired with it), its offsets must have the asked-for spread, and the textures must tile.
#include <doctest/doctest.h>

#include <cmath>

#include "frame/options.h"
#include "frame/paired_reuse.h"
#include "frame/pairing.h"

using namespace rl;

namespace {

PairingView view_of(const PairingTextures& t) { return {t.offsets().data(), t.first().data(), t.sizes().data(), t.count()}; }

// Pixels of a w x h screen whose partner (through any texture, any transform of the frames and
// rounds tried) is on screen but is not paired back; and how many had an on-screen partner.
struct Involution {
  long long on_screen = 0, broken = 0, self = 0;
};
Involution check_involution(const PairingView& v, int w, int h, int frames, bool transpose) {
  Involution r;
  for (uint32_t frame = 0; frame < uint32_t(frames); ++frame)
    for (int round = 0; round < 2; ++round)
      for (int t = 0; t < v.count; ++t) {
        const PairingTransform m = PairingView::transform(t, v.sizes[t], frame, 7 + frame % 3, frame % 2, round);
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x) {
            int px, py;
            v.partner(t, m, x, y, px, py, transpose);
            if (px < 0 || py < 0 || px >= w || py >= h) continue;
            ++r.on_screen;
            if (px == x && py == y) ++r.self;
            int bx, by;
            v.partner(t, m, px, py, bx, by, transpose);
            if (bx != x || by != y) ++r.broken;
          }
      }
  return r;
}

}  // namespace

TEST_SUITE("pairing") {
  TEST_CASE("the partner of the partner is the pixel, on every pixel of every frame (and the planted break is seen)") {
    PairingTextures tex;
    tex.prepare(5, 30);
    REQUIRE(tex.count() == 5);
    const Involution ok = check_involution(view_of(tex), 320, 180, 8, true);
    CHECK(ok.on_screen > 0.85 * 320 * 180 * 8 * 2 * 5);  // a few partners fall off the edges
    CHECK(ok.broken == 0);
    CHECK(ok.self == 0);
    // The planted bias (no transpose of the offset) breaks it wherever a transform swaps the axes.
    const Involution bad = check_involution(view_of(tex), 320, 180, 8, false);
    CHECK(bad.broken > bad.on_screen / 10);
  }

  TEST_CASE("offsets are Gaussian-like with the standard deviation asked for, and tile the torus") {
    for (const float sigma : {2.7f, 5.3f, 16.0f}) {
      const PairingTexture t = make_pairing_texture(254, sigma, 42);
      double sx = 0, sy = 0, mx = 0, my = 0;
      const double n = double(t.size) * t.size;
      for (int y = 0; y < t.size; ++y)
        for (int x = 0; x < t.size; ++x) {
          const int dx = t.dx(x, y), dy = t.dy(x, y);
          REQUIRE((dx != 0 || dy != 0));
          mx += dx, my += dy, sx += double(dx) * dx, sy += double(dy) * dy;
          // The texel the offset leads to (on the torus) leads back.
          const int qx = ((x + dx) % t.size + t.size) % t.size, qy = ((y + dy) % t.size + t.size) % t.size;
          REQUIRE(t.dx(qx, qy) == -dx);
          REQUIRE(t.dy(qx, qy) == -dy);
        }
      const double sdx = std::sqrt(sx / n - (mx / n) * (mx / n)), sdy = std::sqrt(sy / n - (my / n) * (my / n));
      INFO("sigma " << sigma << ": measured " << sdx << ", " << sdy);
      CHECK(std::fabs(mx / n) < 1e-9);  // every offset's partner has its negative
      CHECK(sdx == doctest::Approx(sigma).epsilon(0.15));
      CHECK(sdy == doctest::Approx(sigma).epsilon(0.15));
    }
    CHECK(pairing_sigma(30) == doctest::Approx(16.0).epsilon(0.01));  // the paper's R = 30 -> sigma = 16
  }

  TEST_CASE("textures of different sizes; rebuilt only when the neighbour count or radius changes") {
    PairingTextures tex;
    tex.prepare(3, 30);
    CHECK(tex.sizes()[0] == 254);
    CHECK(tex.sizes()[1] < tex.sizes()[0]);
    CHECK(tex.sizes()[2] < tex.sizes()[1]);
    for (int s : tex.sizes()) CHECK(s % 2 == 0);
    const int16_t* before = tex.offsets().data();
    tex.prepare(3, 30);
    CHECK(tex.offsets().data() == before);
    tex.prepare(4, 30);
    CHECK(tex.count() == 4);
  }

  TEST_CASE("the pair test is the same from either side") {
    GSurface a, b;
    a.valid = b.valid = true;
    a.ns = b.ns = Vec3{0, 0, 1};
    a.depth = 10, b.depth = 10.95f;  // 9.5% of a's depth, 8.7% of b's
    const GPacked pa = pack_surface(a, 0, Rgb(0.5f)), pb = pack_surface(b, 0, Rgb(0.5f));
    CHECK(similar_pair(pa, pb, 0.09f, 25) == similar_pair(pb, pa, 0.09f, 25));
    CHECK(similar_surfaces(a, b, 0.09f, 25) != similar_surfaces(b, a, 0.09f, 25));  // the spiral's test is one-sided
    CHECK(similar_surfaces(a, pb, 0.09f, 25) == similar_surfaces(a, b, 0.09f, 25));  // against a stored surface: the same test
    CHECK(similar_surfaces(b, pa, 0.09f, 25) == similar_surfaces(b, a, 0.09f, 25));
  }

  TEST_CASE("paired reuse needs pairwise MIS, and ReSTIR DI's neighbour visibility") {
    Options o;
    o.integrator = "restir-di";
    set_option(o, "di.spatial_pairing", "paired");
    CHECK_NOTHROW(validate_options(o));
    set_option(o, "di.spatial_mis", "generalized-balance");
    CHECK_THROWS_WITH_AS(validate_options(o), doctest::Contains("needs di.spatial_mis = pairwise"), OptionError);
    set_option(o, "di.spatial_mis", "pairwise");
    set_option(o, "di.neighbor_visibility", "false");
    CHECK_THROWS_WITH_AS(validate_options(o), doctest::Contains("needs di.neighbor_visibility = true"), OptionError);
  }
}
