#include "frame/options.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "frame/integrator.h"

namespace rl {

void set_option(Options& o, std::string_view key, std::string_view value) {
  OptionSetter s{key, value};
  visit_options(o, s);
  if (!s.found) {
    // Keys of earlier versions whose meaning now lives in one place.
    for (const char* old : {"pt.max_depth", "gi.max_depth", "pt.nee", "pt.bsdf_sampling", "pt.russian_roulette"})
      if (key == old)
        throw OptionError("option '" + std::string(key) + "' was replaced by 'path." + std::string(key.substr(key.find('.') + 1)) +
                          "' (one setting for every integrator)");
    throw OptionError("unknown option '" + std::string(key) + "' (see `restir options`)");
  }
  if (std::find(o.explicit_keys.begin(), o.explicit_keys.end(), key) == o.explicit_keys.end()) o.explicit_keys.emplace_back(key);
}

void set_option_assignment(Options& o, std::string_view a) {
  auto eq = a.find('=');
  if (eq == std::string_view::npos || eq == 0) throw OptionError("expected key=value, got '" + std::string(a) + "'");
  set_option(o, a.substr(0, eq), a.substr(eq + 1));
}

namespace {
// A --config key (or a study's base) set to the value it already has is not recorded as explicit:
// a whole echoed configuration (save-config, a sidecar's options) names every group, and its
// unchanged keys are no choice that the integrator could ignore (check_option_groups).
void set_config_option(Options& o, const std::string& key, const std::string& value) {
  const bool was_explicit = std::find(o.explicit_keys.begin(), o.explicit_keys.end(), key) != o.explicit_keys.end();
  const auto before = option_values(o);
  set_option(o, key, value);
  if (!was_explicit && option_values(o) == before) std::erase(o.explicit_keys, key);
}

void apply_json_node(Options& o, const nlohmann::json& j, const std::string& prefix) {
  if (!j.is_object()) throw OptionError("config: expected a JSON object at '" + prefix + "'");
  for (auto it = j.begin(); it != j.end(); ++it) {
    std::string key = prefix.empty() ? it.key() : prefix + "." + it.key();
    const auto& v = it.value();
    if (v.is_object()) {
      apply_json_node(o, v, key);
    } else if (v.is_string()) {
      set_config_option(o, key, v.get<std::string>());
    } else if (v.is_boolean()) {
      set_config_option(o, key, v.get<bool>() ? "true" : "false");
    } else if (v.is_number_integer() || v.is_number_unsigned()) {
      set_config_option(o, key, v.dump());
    } else if (v.is_number_float()) {
      set_config_option(o, key, fmt::format("{}", v.get<double>()));  // not via float: 1e300 must stay out of range
    } else {
      throw OptionError("config: option '" + key + "' has an unsupported JSON type");
    }
  }
}
// Emits typed JSON values so an echoed config can be fed back with --config.
struct JsonWriter {
  nlohmann::ordered_json& j;
  template <class T>
  void operator()(const char* k, T& field, const char*, Range = {}) {
    if constexpr (NamedEnum<T>) j[k] = std::string(enum_name(field));
    else j[k] = field;
  }
};
}  // namespace

void apply_options_json(Options& o, std::string_view text) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::out_of_range& e) {  // a number beyond double's range (1e400)
    std::string what = e.what();
    auto at = what.find("] ");
    throw OptionError("config: invalid JSON: " + (at == std::string::npos ? what : what.substr(at + 2)));
  } catch (const nlohmann::json::exception& e) {
    throw OptionError(std::string("config: invalid JSON: ") + e.what());
  }
  apply_json_node(o, j, "");
}

void apply_options_file(Options& o, const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw OptionError("config: '" + path + "' is a directory, not a JSON file");
  std::ifstream in(path);
  if (!in) throw OptionError("config: cannot open '" + path + "'");
  std::stringstream ss;
  ss << in.rdbuf();
  try {
    apply_options_json(o, ss.str());
  } catch (const OptionError& e) {
    throw OptionError(path + ": " + e.what());
  }
}

std::vector<std::pair<std::string, std::string>> option_values(const Options& o) {
  OptionPrinter p;
  visit_options(const_cast<Options&>(o), p);  // the printer only reads
  return std::move(p.out);
}

std::string options_to_json(const Options& o, int indent) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  JsonWriter typed{j};
  visit_options(const_cast<Options&>(o), typed);
  return j.dump(indent);
}

std::string options_help() {
  OptionHelp h;
  Options defaults;
  visit_options(defaults, h);
  std::string s = "Options (set with --set key=value or a JSON --config file):\n";
  for (const auto& l : h.lines)
    s += fmt::format("  {:<26} {:<34} default {:<10} {}\n", l.key, "<" + l.type + ">", l.default_value, l.help);
  return s;
}

void validate_options(const Options& o) {
  // 16384 x 16384 is allowed per axis, but not a 268-megapixel frame: 64 MPixel at most.
  if (int64_t(o.film.width) * o.film.height > int64_t(64) << 20)
    throw OptionError(fmt::format("resolution {}x{} is too large (at most 64 megapixels)", o.film.width, o.film.height));
  // ReSTIR PT stores a walk's vertices in fixed arrays (64 bounces); ReSTIR GI needs one bounce.
  if ((o.integrator == "restir-pt" || o.integrator == "restir-gi") && (o.path.max_depth < 1 || o.path.max_depth > 64))
    throw OptionError(fmt::format("path.max_depth = {}: {} renders 1 to 64 bounces", o.path.max_depth, o.integrator));
  // No candidate at all: every ReSTIR DI pixel would be black, silently.
  if (o.integrator == "restir-di" && o.di.light_candidates == 0 && o.di.bsdf_candidates == 0)
    throw OptionError("di.light_candidates and di.bsdf_candidates are both 0: restir-di needs at least one candidate");
  // The BVH backends run pt and the ReSTIR integrators; ssr still traces ray by ray on the CPU,
  // and running it "on cuda" would silently run it on the CPU.
  if (o.render.backend != Backend::cpu && o.integrator == "ssr")
    throw OptionError(fmt::format("render.backend = {}: ssr runs on the cpu backend only (pt, restir-di, restir-gi and restir-pt run on every backend)",
                                  enum_name(o.render.backend)));
  check_option_groups(o);
}

}  // namespace rl
