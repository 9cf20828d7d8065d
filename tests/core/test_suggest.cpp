#include <doctest/doctest.h>

#include "core/suggest.h"

using namespace rl;

TEST_CASE("suggest: edit distance counts insertions, deletions, substitutions and neighbour swaps") {
  CHECK(edit_distance("", "") == 0);
  CHECK(edit_distance("abc", "") == 3);
  CHECK(edit_distance("kitten", "sitting") == 3);
  CHECK(edit_distance("radius", "raduis") == 1);   // one swap, not two substitutions
  CHECK(edit_distance("Shape", "shape") == 0);     // case-insensitive
  CHECK(edit_distance("spatial", "spatail") == 1);
}

TEST_CASE("suggest: the closest name only when it is close") {
  const std::vector<std::string> keys = {"pt.spatial_radius", "pt.spatial_neighbors", "di.spatial_radius"};
  CHECK(closest_name("pt.spatial_radus", keys) == "pt.spatial_radius");
  CHECK(closest_name("pt.spatial_neighbours", keys) == "pt.spatial_neighbors");
  CHECK(closest_name("render.spp", keys).empty());
  CHECK(did_you_mean("pt.spatial_radus", keys) == " (did you mean 'pt.spatial_radius'?)");
  CHECK(did_you_mean("zzz", keys).empty());
  // Short words: one letter wrong at most.
  CHECK(closest_name("spo", {"spot", "disk"}) == "spot");
  CHECK(closest_name("sx", {"spot", "disk"}).empty());
}
