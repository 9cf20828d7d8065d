#include <doctest/doctest.h>

#include "frame/options.h"

using namespace rl;

TEST_CASE("options: set, echo and JSON round-trip through the one visit list") {
  Options o;
  set_option(o, "path.max_depth", "7");
  set_option(o, "output.tonemap", "modified-reinhard");
  set_option_assignment(o, "render.seed=42");
  CHECK(o.path.max_depth == 7);
  CHECK(o.output.tonemap == Tonemap::modified_reinhard);
  CHECK(o.render.seed == 42);

  Options back;
  apply_options_json(back, options_to_json(o));
  CHECK(option_values(back) == option_values(o));

  Options nested;
  apply_options_json(nested, R"({"path": {"max_depth": 3, "nee": false}, "film.width": 32})");
  CHECK(nested.path.max_depth == 3);
  CHECK_FALSE(nested.path.nee);
  CHECK(nested.film.width == 32);
}

TEST_CASE("options: unknown keys, bad values and absurd resolutions are errors") {
  Options o;
  CHECK_THROWS_AS(set_option(o, "path.max_detph", "3"), OptionError);
  CHECK_THROWS_AS(set_option(o, "path.max_depth", "three"), OptionError);
  CHECK_THROWS_AS(set_option(o, "path.max_depth", "-1"), OptionError);
  CHECK_THROWS_AS(set_option(o, "film.width", "0"), OptionError);
  CHECK_THROWS_AS(set_option(o, "film.width", "100000"), OptionError);
  CHECK_THROWS_AS(set_option(o, "output.tonemap", "filmic"), OptionError);
  CHECK_THROWS_AS(set_option(o, "render.spp", "1.5"), OptionError);
  CHECK_THROWS_AS(apply_options_json(o, "{\"path\": {\"bogus\": 1}}"), OptionError);
  CHECK_THROWS_AS(apply_options_json(o, "{not json"), OptionError);
  o.film.width = 16384;
  o.film.height = 16384;
  CHECK_THROWS_AS(validate_options(o), OptionError);
}

TEST_CASE("options: help lists every key once") {
  std::string h = options_help();
  for (const auto& [k, v] : option_values(Options{})) {
    auto first = h.find("  " + k + " ");
    CHECK_MESSAGE(first != std::string::npos, k);
    CHECK(h.find("  " + k + " ", first + 1) == std::string::npos);
  }
}
