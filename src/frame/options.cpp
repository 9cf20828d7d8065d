#include "frame/options.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/suggest.h"
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
    std::vector<std::string> keys;
    for (auto& [k, v] : option_values(Options{})) keys.push_back(k);
    std::string hint = did_you_mean(key, keys);
    throw OptionError("unknown option '" + std::string(key) + "'" + (hint.empty() ? " (see `restir options`)" : hint));
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

std::string options_help(std::string_view prefix) {
  OptionHelp h;
  Options defaults;
  visit_options(defaults, h);
  std::string s = "Options (set with --set key=value or a JSON --config file):\n";
  std::vector<std::string> keys;
  for (const auto& l : h.lines) {
    keys.push_back(l.key);
    if (l.key.starts_with(prefix))
      s += fmt::format("  {:<26} {:<34} default {:<10} {}\n", l.key, "<" + l.type + ">", l.default_value, l.help);
  }
  if (std::none_of(keys.begin(), keys.end(), [&](const std::string& k) { return k.starts_with(prefix); }))
  {
    std::vector<std::string> heads;  // each key cut to the prefix's length: a misspelt prefix is near one
    for (const std::string& k : keys) heads.push_back(k.substr(0, prefix.size()));
    throw OptionError("no option key starts with '" + std::string(prefix) + "'" + did_you_mean(prefix, heads));
  }
  return s;
}

bool is_explicit(const Options& o, std::string_view key) {
  return std::find(o.explicit_keys.begin(), o.explicit_keys.end(), key) != o.explicit_keys.end();
}

std::pair<int, int> max_depth_range(std::string_view integrator) {
  // ReSTIR PT counts a path's vertices in bytes (64 bounces at most); ReSTIR GI needs one bounce.
  if (integrator == "restir-pt" || integrator == "restir-gi") return {1, 64};
  return {0, 1024};
}

std::vector<std::string> fit_defaults_to_integrator(Options& o, bool sequence) {
  std::vector<std::string> notes;
  // A value the scene file implied (not explicit) outside the integrator's range is brought inside
  // it, saying so: the Cornell box's maxdepth 65 is a path tracer's "until absorbed", not a choice.
  if (const auto [lo, hi] = max_depth_range(o.integrator);
      !is_explicit(o, "path.max_depth") && (o.path.max_depth < lo || o.path.max_depth > hi)) {
    const int fitted = std::clamp(o.path.max_depth, lo, hi);
    notes.push_back(fmt::format("{} renders {} to {} bounces: path.max_depth {} (from the scene) becomes {}; "
                                "set path.max_depth to choose", o.integrator, lo, hi, o.path.max_depth, fitted));
    o.path.max_depth = fitted;
  }
  const bool restir = o.integrator.starts_with("restir-");
  if (!sequence || !restir) return notes;
  // ReSTIR reuses samples over the frames of a sequence (Bitterli et al. 2020, sec. 4): n samples
  // per pixel in one frame would be n independent chains that never reuse over time. Unless told
  // otherwise, render what a real-time renderer does: 1 sample per pixel per frame, a sequence.
  const bool spp_set = is_explicit(o, "render.spp"), frames_set = is_explicit(o, "render.frames");
  if (!spp_set && !frames_set) {
    const int spp = o.render.spp;
    o.render.spp = 1;
    o.render.frames = std::max(o.render.frames, kRestirDefaultFrames);
    notes.push_back(fmt::format("{} renders a sequence: 1 sample per pixel per frame, {} frames, the last one written "
                                "(not {} spp in one frame); set render.spp and render.frames (--spp, --frames) to choose",
                                o.integrator, o.render.frames, spp));
  } else if (!spp_set && o.render.spp != 1) {
    notes.push_back(fmt::format("{}: 1 sample per pixel per frame (not the {} spp the scene file asks); set render.spp to choose",
                                o.integrator, o.render.spp));
    o.render.spp = 1;
  } else if (o.render.frames == 1 && o.render.spp > 1) {
    notes.push_back(fmt::format("warning: {} with {} spp in 1 frame renders {} independent ReSTIR chains, with no temporal "
                                "reuse; a sequence (--spp 1 --frames {}) is what ReSTIR is for",
                                o.integrator, o.render.spp, o.render.spp, kRestirDefaultFrames));
  }
  return notes;
}

namespace {
// Paired spatial reuse exchanges the two shifts of a pair between partners (frame/paired_reuse.h):
// the pairwise family of MIS weights (pairwise, symmetric and asymmetric ratio) reads only those;
// the others need shifts it does not make, and ReSTIR DI's partner must evaluate a neighbour's
// target as the canonical one does (with visibility).
void check_paired_reuse(const Options& o) {
  const auto check = [&](const char* group, const ReuseOptions& r) {
    if (r.spatial_pairing != SpatialPairing::paired || restir::detail::pairwise_family(r.spatial_mis)) return;
    throw OptionError(fmt::format("{}.spatial_pairing = paired: needs {}.spatial_mis = pairwise, symmetric-ratio or "
                                  "asymmetric-ratio (the pairs exchange the two shifts of each pair), not {}",
                                  group, group, enum_name(r.spatial_mis)));
  };
  if (o.integrator == "restir-di" || o.integrator == "restir-pt") check("di", o.di.reuse);
  if (o.integrator == "restir-gi") check("gi", o.gi.reuse);
  if (o.integrator == "restir-pt") check("pt", o.pt.reuse);
  if (o.di.reuse.spatial_pairing == SpatialPairing::paired && o.di.visibility_reuse && !o.di.neighbor_visibility &&
      (o.integrator == "restir-di" || o.integrator == "restir-pt"))
    throw OptionError("di.spatial_pairing = paired: needs di.neighbor_visibility = true with di.visibility_reuse (a partner's "
                      "shift is evaluated once, as the canonical target, with visibility)");
}

// RGB weights sum m_i F W J over the inputs (mis.h): the MIS weights must be inside the w_i, the
// integrator's bridge must give F, and ReSTIR DI's F must need no shadow ray (its target holds V).
void check_rgb_weights(const Options& o) {
  const auto check = [&](const char* group, const ReuseOptions& r) {
    if (!r.rgb_weights || r.spatial_mis != restir::ReuseMis::one_over_z) return;
    throw OptionError(fmt::format("{}.rgb_weights = true: needs {}.spatial_mis other than one-over-z "
                                  "(1/Z normalizes the selected sample alone, so the inputs' colours have no weights to sum)", group, group));
  };
  if (o.integrator == "restir-di" || o.integrator == "restir-pt") check("di", o.di.reuse);
  if (o.integrator == "restir-pt") check("pt", o.pt.reuse);
  if (o.integrator == "restir-gi" && o.gi.reuse.rgb_weights)
    throw OptionError("gi.rgb_weights = true: restir-gi has no RGB resampling weights (restir-pt and restir-di do)");
  if ((o.integrator == "restir-di" || o.integrator == "restir-pt") && o.di.reuse.rgb_weights && !o.di.visibility_reuse)
    throw OptionError("di.rgb_weights = true: needs di.visibility_reuse = true (each input's colour must carry its visibility "
                      "without a shadow ray of its own)");
}
}  // namespace

// Resampled NEE (restir_pt/walk.h, nee_light): the chosen light point's density has no closed
// form, only its RIS contribution weight, so no shift may replay the light choice from another
// vertex (random replay; the hybrid shift's replay of a path without reconnection vertex). Forced
// reconnection at the light vertex keeps every NEE path's light vertex, or an earlier one.
void check_nee_candidates(const Options& o) {
  if (o.integrator != "restir-pt" || o.pt.nee_candidates <= 1) return;
  if (o.pt.shift == ShiftMapping::reconnection || (o.pt.shift == ShiftMapping::hybrid && o.pt.force_nee_reconnection)) return;
  throw OptionError(fmt::format("pt.nee_candidates = {}: needs pt.shift = reconnection, or pt.shift = hybrid with "
                                "pt.force_nee_reconnection = true (a shift cannot replay a resampled light choice); set one "
                                "of them, or pt.nee_candidates = 1",
                                o.pt.nee_candidates));
}

// Replay compaction reorders the partners' shifts of paired reuse: without pairing there is no
// such pass to reorder.
void check_replay_compaction(const Options& o) {
  if (o.integrator != "restir-pt" || !o.pt.replay_compaction || o.pt.reuse.spatial_pairing == SpatialPairing::paired) return;
  throw OptionError("pt.replay_compaction = true: needs pt.spatial_pairing = paired (it schedules the partners' shifts of "
                    "paired reuse; the spiral's shifts are made inside each pixel's resampling)");
}

void validate_options(const Options& o) {
  // 16384 x 16384 is allowed per axis, but not a 268-megapixel frame: 64 MPixel at most.
  if (int64_t(o.film.width) * o.film.height > int64_t(64) << 20)
    throw OptionError(fmt::format("resolution {}x{} is too large (at most 64 megapixels)", o.film.width, o.film.height));
  // ReSTIR PT counts a path's vertices in bytes (64 bounces at most); ReSTIR GI needs one bounce.
  if (const auto [lo, hi] = max_depth_range(o.integrator); o.path.max_depth < lo || o.path.max_depth > hi)
    throw OptionError(fmt::format("path.max_depth = {}: {} renders {} to {} bounces; set path.max_depth to a value in [{}, {}]{}",
                                  o.path.max_depth, o.integrator, lo, hi, lo, hi,
                                  hi < 1024 ? " (or --integrator pt for longer paths)" : ""));
  // No candidate at all: every ReSTIR DI pixel would be black, silently.
  if (o.integrator == "restir-di" && o.di.light_candidates == 0 && o.di.bsdf_candidates == 0)
    throw OptionError("di.light_candidates and di.bsdf_candidates are both 0: restir-di needs at least one candidate");
  check_paired_reuse(o);
  check_rgb_weights(o);
  check_nee_candidates(o);
  check_replay_compaction(o);
  if (is_explicit(o, "denoise.oidn_library") && o.denoise.method != DenoiseMethod::oidn)
    throw OptionError(fmt::format("denoise.oidn_library is read only by denoise.method = oidn (not {})", enum_name(o.denoise.method)));
  check_option_groups(o);
}

}  // namespace rl
