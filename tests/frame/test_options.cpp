#include <algorithm>
#include <doctest/doctest.h>

#include "frame/options.h"
#include "frame/render.h"

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

// Issue 43: a key set explicitly that the integrator does not read is an error naming the integrator
// and the groups it reads; a scene file's values are not explicit; the viewer's panel is not checked.
TEST_CASE("options: an explicitly set key the integrator does not read is an error") {
  Options o;
  set_option(o, "integrator", "restir-di");
  set_option(o, "pt.spatial_radius", "10");
  CHECK_THROWS_WITH_AS(validate_options(o),
                       "option 'pt.spatial_radius' is not read by the integrator restir-di (it reads di.*, film.*, render.*, output.*): "
                       "remove it, or set it only where the integrator reads it (a study axis value null leaves a key unset)",
                       OptionError);
  set_option(o, "integrator", "restir-pt");  // reads pt.* (and di.* for pt.direct = restir-di)
  CHECK_NOTHROW(validate_options(o));
  set_option(o, "di.light_candidates", "8");
  CHECK_NOTHROW(validate_options(o));
  o.integrator = "pt";
  CHECK_THROWS_WITH_AS(validate_options(o), doctest::Contains("'pt.spatial_radius' is not read by the integrator pt"), OptionError);
  o.integrator = "ssr";  // ssr's lit colour is the path tracer at depth 1: it reads path.*
  Options ssr;
  set_option(ssr, "integrator", "ssr");
  set_option(ssr, "path.nee", "false");
  set_option(ssr, "render.spp", "2");
  set_option(ssr, "film.width", "32");
  set_option(ssr, "output.exposure", "1");
  CHECK_NOTHROW(validate_options(ssr));
  // Assigning a field is not setting a key: only set_option (CLI, config, study, JSON) records one.
  Options direct;
  direct.integrator = "restir-di";
  direct.pt.reuse.spatial_radius = 3;
  CHECK_NOTHROW(validate_options(direct));
  // A config file's keys are explicit too.
  Options cfg;
  apply_options_json(cfg, R"({"integrator": "restir-gi", "di": {"spatial_neighbors": 2}})");
  CHECK_THROWS_WITH_AS(validate_options(cfg), doctest::Contains("'di.spatial_neighbors' is not read by the integrator restir-gi"),
                       OptionError);
}

TEST_CASE("options: an echoed configuration (every group) feeds back through --config") {
  // save-config and the sidecars write every key; the unchanged ones are no choice.
  Options saved;
  set_option(saved, "integrator", "restir-di");
  set_option(saved, "di.spatial_neighbors", "3");  // not the default (5)
  const std::string echoed = options_to_json(saved, 2);
  Options loaded;
  apply_options_json(loaded, echoed);
  CHECK(options_to_json(loaded, 2) == echoed);
  CHECK_NOTHROW(validate_options(loaded));
  CHECK(std::find(loaded.explicit_keys.begin(), loaded.explicit_keys.end(), "di.spatial_neighbors") != loaded.explicit_keys.end());
  CHECK(std::find(loaded.explicit_keys.begin(), loaded.explicit_keys.end(), "pt.spatial_radius") == loaded.explicit_keys.end());
  // One changed key of another group is still refused, even inside an echoed configuration.
  saved.pt.reuse.spatial_radius = 11;
  Options changed;
  apply_options_json(changed, options_to_json(saved, 2));
  CHECK_THROWS_WITH_AS(validate_options(changed), doctest::Contains("'pt.spatial_radius' is not read by the integrator restir-di"),
                       OptionError);
  // A key set explicitly earlier stays explicit when the config repeats its value.
  Options cli;
  set_option(cli, "integrator", "restir-di");
  set_option(cli, "pt.spatial_radius", std::to_string(Options{}.pt.reuse.spatial_radius));
  apply_options_json(cli, R"({"pt": {"spatial_radius": )" + std::to_string(Options{}.pt.reuse.spatial_radius) + "}}");
  CHECK_THROWS_AS(validate_options(cli), OptionError);
}

TEST_CASE("options: a scene file's values are not explicit keys") {
  Options o;
  SceneHints hints;
  hints.max_depth = 65;  // the Cornell box's Integrator "path" "integer maxdepth" 65
  set_option(o, "integrator", "restir-di");
  apply_scene_hints(o, hints);
  CHECK(o.path.max_depth == 65);
  CHECK(o.explicit_keys == std::vector<std::string>{"integrator"});
  CHECK_NOTHROW(validate_options(o));
}
