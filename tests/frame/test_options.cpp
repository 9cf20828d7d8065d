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
                       "option 'pt.spatial_radius' is not read by the integrator restir-di (it reads di.*, film.*, render.*, denoise.*, output.*): "
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

TEST_CASE("options: a mistyped key names the closest one") {
  Options o;
  CHECK_THROWS_WITH_AS(set_option(o, "pt.spatial_radus", "10"), doctest::Contains("did you mean 'pt.spatial_radius'?"), OptionError);
  CHECK_THROWS_WITH_AS(set_option(o, "nothing.like.it", "1"), doctest::Contains("see `restir options`"), OptionError);
}

TEST_CASE("options: a scene's max depth is fitted to restir-pt, an explicit one is refused with what to set") {
  SceneHints hints;
  hints.max_depth = 65;  // the Cornell box
  Options o;
  set_option(o, "integrator", "restir-pt");
  apply_scene_hints(o, hints);
  CHECK_THROWS_AS(validate_options(o), OptionError);
  const auto notes = fit_defaults_to_integrator(o, false);
  REQUIRE(notes.size() == 1);
  CHECK(notes[0].find("path.max_depth 65 (from the scene) becomes 64") != std::string::npos);
  CHECK(o.path.max_depth == 64);
  CHECK_NOTHROW(validate_options(o));
  // The path tracer renders the scene's 65 as it is.
  Options p;
  apply_scene_hints(p, hints);
  CHECK(fit_defaults_to_integrator(p, true).empty());
  CHECK(p.path.max_depth == 65);
  // Set explicitly, it is the user's choice: refused, saying what to set.
  Options e;
  set_option(e, "integrator", "restir-gi");
  set_option(e, "path.max_depth", "65");
  CHECK(fit_defaults_to_integrator(e, true).size() == 1);  // only the sequence note
  CHECK(e.path.max_depth == 65);
  CHECK_THROWS_WITH_AS(validate_options(e), doctest::Contains("set path.max_depth to a value in [1, 64]"), OptionError);
}

TEST_CASE("options: a ReSTIR render is a 1-spp sequence unless told otherwise") {
  SceneHints hints;
  hints.spp = 64;
  auto with = [&](const char* integrator, std::vector<std::string> sets) {
    Options o;
    apply_scene_hints(o, hints);
    set_option(o, "integrator", integrator);
    for (const auto& s : sets) set_option_assignment(o, s);
    return o;
  };
  Options a = with("restir-pt", {});
  auto notes = fit_defaults_to_integrator(a, true);
  CHECK(a.render.spp == 1);
  CHECK(a.render.frames == kRestirDefaultFrames);
  REQUIRE(notes.size() == 1);
  CHECK(notes[0].find("not 64 spp in one frame") != std::string::npos);
  // Without `sequence` (a study, the viewer) nothing about spp or frames changes.
  Options s = with("restir-di", {});
  CHECK(fit_defaults_to_integrator(s, false).empty());
  CHECK(s.render.spp == 64);
  // Frames given, spp from the scene: 1 spp per frame.
  Options f = with("restir-gi", {"render.frames=4"});
  CHECK(fit_defaults_to_integrator(f, true).size() == 1);
  CHECK((f.render.spp == 1 && f.render.frames == 4));
  // Both given, many spp in one frame: unchanged, and a warning.
  Options w = with("restir-di", {"render.spp=8", "render.frames=1"});
  notes = fit_defaults_to_integrator(w, true);
  REQUIRE(notes.size() == 1);
  CHECK(notes[0].starts_with("warning: restir-di with 8 spp in 1 frame"));
  CHECK((w.render.spp == 8 && w.render.frames == 1));
  // The path tracer keeps the scene's samples.
  Options p = with("pt", {});
  CHECK(fit_defaults_to_integrator(p, true).empty());
  CHECK((p.render.spp == 64 && p.render.frames == 1));
}
