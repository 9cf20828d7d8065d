// Resampled next-event estimation in ReSTIR PT's walks (pt.nee_candidates; walk.h, nee_light).
// At a fixed primary hit, the NEE-tagged paths of length 2 estimate ∫ m_nee f over the light
// points (m_nee the balance heuristic of the source densities): with one light sample and with N
// resampled candidates alike, so their means over independent walks must agree. Checked on Veach
// MIS (four spheres of very different sizes and radiances: the source pmf is far from the
// contribution) and the Cornell box (one light: the candidates differ in cosine and distance).
// The check's power: the resampled point weighted by its source density instead of its RIS
// contribution weight (PathSettings::nee_source_density) misses by many standard errors, and RIS
// must lower the variance: eight candidates cut it about 8x on both scenes.
#include <doctest/doctest.h>

#include <cmath>

#include "frame/light_tiles.h"
#include "integrators/restir_pt/walk.h"
#include "pt_fixture.h"

using namespace rl;
using namespace rl::test;

namespace {

struct Estimate {
  double mean = 0, variance = 0;  // of one walk's NEE estimate; the mean's variance is variance / n
  int n = 0;
};

// Mean and variance over `walks` walks of Σ_{NEE paths of length 2} luminance(m f) / p, where p is the
// density the walk offers the path with (the light's, or 1 / W for resampled NEE).
// tile_size > 0: every walk draws its candidates from a fresh light tile of that many emitters and
// environment directions (LightTiles, one tile, the walk's index as the frame).
Estimate nee_estimate(const PtFixture& fx, const GSurface& s, int candidates, bool source_density, int walks, int tile_size = 0) {
  PathSettings ps;
  ps.path.max_depth = 1;
  ps.pt.shift = ShiftMapping::hybrid;
  ps.pt.force_nee_reconnection = true;
  ps.pt.nee_candidates = candidates;
  ps.nee_source_density = source_density;
  const PathWorld world = fx.world();
  const EmbreeTracer tracer = fx.tracer();
  pt_detail::Walk w;
  double sum = 0, sum2 = 0;
  LightTiles tiles;
  for (int i = 0; i < walks; ++i) {
    double value = 0;
    LightTileView tile;
    if (tile_size > 0) {
      tiles.build(*fx.lights, 1, tile_size, uint32_t(i), 77, 0, tile_size);
      tile = {tiles.entries().data(), uint32_t(tiles.size()), tiles.env_size() > 0 ? tiles.env_entries().data() : nullptr,
              uint32_t(tiles.env_size())};
    }
    pt_detail::walk_from(world, tracer, ps, s, hash_combine(uint64_t(candidates) * 7919 + 1, uint64_t(i)), w,
                         [&](const pt_detail::OfferedPath& o) {
                           if (o.nee_tag && o.n == 2 && o.path_pdf > 0)
                             value += luminance(pt_detail::offered_contribution(w, o)) / o.path_pdf;
                         }, tile);
    sum += value, sum2 += value * value;
  }
  Estimate e;
  e.n = walks;
  e.mean = sum / walks;
  e.variance = std::max(0.0, sum2 / walks - e.mean * e.mean);
  return e;
}

double z_score(const Estimate& a, const Estimate& b) {
  const double se = std::sqrt(a.variance / a.n + b.variance / b.n);
  return se > 0 ? std::fabs(a.mean - b.mean) / se : 0.0;
}

struct Comparison {
  int surfaces = 0;
  double worst_z = 0;          // resampled against one sample, over the surfaces
  double planted_best_z = 0;   // source density instead of W: the largest miss
  double variance_ratio = 0;   // Σ variance (resampled) / Σ variance (one sample)
};

Comparison compare_on(const std::string& path, int candidates, int walks, int tile_size = 0) {
  PtFixture fx(path, 16);
  Comparison c;
  double v1 = 0, vn = 0;
  Pcg32 rng(2024);
  for (int tries = 0; tries < 400 && c.surfaces < 6; ++tries) {
    const GSurface& s = fx.random_surface(rng);
    if (!s.valid || bsdf_is_delta(s.bsdf)) continue;
    const Estimate one = nee_estimate(fx, s, 1, false, walks);
    if (!(one.mean > 0)) continue;
    const Estimate many = nee_estimate(fx, s, candidates, false, walks, tile_size);
    const Estimate planted = nee_estimate(fx, s, candidates, true, walks, tile_size);
    c.worst_z = std::max(c.worst_z, z_score(one, many));
    c.planted_best_z = std::max(c.planted_best_z, z_score(one, planted));
    v1 += one.variance, vn += many.variance;
    ++c.surfaces;
  }
  c.variance_ratio = v1 > 0 ? vn / v1 : 0;
  return c;
}

}  // namespace

TEST_SUITE("restir_pt") {
  TEST_CASE("pt.nee_candidates: resampled NEE estimates the same direct light as one light sample (Veach MIS, Cornell box)") {
    for (const std::string& path : {shared_scene("veach-mis/scene-v4.pbrt"), shared_scene("cornell-box/scene-v4.pbrt")}) {
      const Comparison c = compare_on(path, 8, 3000);
      MESSAGE(path << ": " << c.surfaces << " surfaces, worst |z| " << c.worst_z << ", planted best |z| " << c.planted_best_z
                   << ", variance ratio (8 candidates / 1) " << c.variance_ratio);
      CAPTURE(path);
      CHECK(c.surfaces == 6);
      CHECK(c.worst_z < 4.5);         // six surfaces: a false alarm at 4.5 se is ~4e-5
      CHECK(c.planted_best_z > 8);    // the test sees a density that ignores the resampling
      CHECK(c.variance_ratio < 0.5);  // measured 0.11 (Veach MIS) and 0.13 (Cornell box)
    }
  }

  TEST_CASE("pt.nee_candidates: candidates from light tiles (tiny, redrawn per walk) estimate the same direct light (teapots, Veach MIS)") {
    // The teapots are lit by an environment map: its candidates take the tile's presampled directions.
    for (const std::string& path : {own_scene("teapot.pbrt"), shared_scene("veach-mis/scene-v4.pbrt")}) {
      const Comparison c = compare_on(path, 8, 3000, 4);
      MESSAGE(path << " (tiles of 4): " << c.surfaces << " surfaces, worst |z| " << c.worst_z << ", planted best |z| "
                   << c.planted_best_z << ", variance ratio " << c.variance_ratio);
      CAPTURE(path);
      CHECK(c.surfaces == 6);
      CHECK(c.worst_z < 4.5);
      CHECK(c.planted_best_z > 8);
    }
  }

  TEST_CASE("pt.nee_candidates > 1: refused where a shift would replay the light choice") {
    Options o;
    o.integrator = "restir-pt";
    set_option(o, "pt.nee_candidates", "4");
    CHECK_THROWS_WITH_AS(validate_options(o), doctest::Contains("pt.force_nee_reconnection"), OptionError);
    set_option(o, "pt.force_nee_reconnection", "true");
    CHECK_NOTHROW(validate_options(o));
    set_option(o, "pt.shift", "random-replay");
    CHECK_THROWS_WITH_AS(validate_options(o), doctest::Contains("pt.nee_candidates"), OptionError);
    set_option(o, "pt.shift", "reconnection");
    CHECK_NOTHROW(validate_options(o));
    set_option(o, "pt.nee_candidates", "1");
    set_option(o, "pt.shift", "random-replay");
    CHECK_NOTHROW(validate_options(o));
  }
}
