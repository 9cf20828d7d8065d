#include "study/study_file.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "study/results.h"

namespace rl::study {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

[[noreturn]] void fail(const std::string& file, const std::string& msg) { throw StudyError(file + ": " + msg); }

void check_keys(const json& j, const std::set<std::string>& allowed, const std::string& file, const std::string& where) {
  if (!j.is_object()) fail(file, where + " must be an object");
  for (const auto& [k, v] : j.items()) {
    if (!allowed.count(k)) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      fail(file, fmt::format("unknown key '{}'{} (allowed: {})", k, where.empty() ? "" : " in " + where, list));
    }
  }
}

std::string value_text(const json& v, const std::string& file, const std::string& key) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  if (v.is_number_integer() || v.is_number_unsigned()) return v.dump();
  if (v.is_number_float()) {
    double d = v.get<double>();
    if (d == std::floor(d) && std::abs(d) < 1e15) return fmt::format("{}", int64_t(d));
    return fmt::format("{}", d);
  }
  fail(file, fmt::format("value of '{}' must be a string, number or boolean", key));
}

// Flattens {"path": {"max_depth": 3}} or {"path.max_depth": 3} into (key, text) pairs.
void flatten(const json& j, const std::string& prefix, std::vector<std::pair<std::string, std::string>>& out,
             const std::string& file) {
  for (const auto& [k, v] : j.items()) {
    std::string key = prefix.empty() ? k : prefix + "." + k;
    if (v.is_object()) flatten(v, key, out, file);
    else out.emplace_back(key, value_text(v, file, key));
  }
}

// Throws naming the file if key=value is not a valid option.
void check_option(const std::string& key, const std::string& value, const std::string& file) {
  if (key == "render.seed" || key == "render.frames")
    fail(file, fmt::format("'{}' is set by the study's \"seeds\" / \"frames\", not as an option", key));
  Options o;
  try {
    set_option(o, key, value);
  } catch (const std::exception& e) {
    fail(file, e.what());
  }
}

std::vector<std::optional<std::string>> axis_values(const json& a, const std::string& key, const std::string& file) {
  std::vector<std::optional<std::string>> vals;
  if (a.contains("values")) {
    if (a.contains("range")) fail(file, fmt::format("axis '{}': give \"values\" or \"range\", not both", key));
    if (!a["values"].is_array() || a["values"].empty()) fail(file, fmt::format("axis '{}': \"values\" must be a non-empty list", key));
    for (const auto& v : a["values"]) vals.push_back(v.is_null() ? std::nullopt : std::optional<std::string>(value_text(v, file, key)));
  } else if (a.contains("range")) {
    const json& r = a["range"];
    check_keys(r, {"from", "to", "step"}, file, "range of axis '" + key + "'");
    for (const char* k : {"from", "to", "step"})
      if (!r.contains(k) || !r[k].is_number()) fail(file, fmt::format("axis '{}': range needs numeric \"{}\"", key, k));
    double from = r["from"].get<double>(), to = r["to"].get<double>(), step = r["step"].get<double>();
    if (!(step > 0)) fail(file, fmt::format("axis '{}': range step must be > 0", key));
    if (to < from) fail(file, fmt::format("axis '{}': range 'to' < 'from'", key));
    const bool integral = r["from"].is_number_integer() && r["step"].is_number_integer();
    const int64_t n = int64_t(std::floor((to - from) / step * (1 + 1e-9))) + 1;
    if (n > 100000) fail(file, fmt::format("axis '{}': range has too many values", key));
    for (int64_t i = 0; i < n; ++i) {
      double v = from + double(i) * step;
      vals.push_back(integral ? fmt::format("{}", int64_t(std::llround(v))) : fmt::format("{}", v));
    }
  } else {
    fail(file, fmt::format("axis '{}': needs \"values\" or \"range\"", key));
  }
  for (const auto& v : vals)
    if (v) check_option(key, *v, file);
  return vals;
}

void parse_axes(const json& j, Study& s, const std::string& file) {
  if (!j.is_array()) fail(file, "\"axes\" must be a list");
  s.axes.clear();
  for (const auto& a : j) {
    check_keys(a, {"key", "values", "range"}, file, "axis");
    if (!a.contains("key") || !a["key"].is_string()) fail(file, "every axis needs a \"key\" (an option key)");
    Axis ax;
    ax.key = a["key"].get<std::string>();
    ax.values = axis_values(a, ax.key, file);
    s.axes.push_back(std::move(ax));
  }
}

void parse_seeds(const json& j, Study& s, const std::string& file) {
  s.seeds.clear();
  if (j.is_number_integer()) {
    int n = j.get<int>();
    if (n < 1 || n > 10000) fail(file, "\"seeds\" count must be in [1, 10000]");
    for (int i = 0; i < n; ++i) s.seeds.push_back(uint64_t(i + 1));
  } else if (j.is_array() && !j.empty()) {
    for (const auto& v : j) {
      if (!v.is_number_unsigned() && !(v.is_number_integer() && v.get<int64_t>() >= 0))
        fail(file, "\"seeds\" must be a count or a list of non-negative integers");
      s.seeds.push_back(v.get<uint64_t>());
    }
  } else {
    fail(file, "\"seeds\" must be a count or a non-empty list");
  }
}

void parse_reference(const json& j, ReferenceSpec& r, const std::string& file) {
  check_keys(j, {"spp", "seed", "options"}, file, "\"reference\"");
  if (j.contains("spp")) {
    if (!j["spp"].is_number_integer() || j["spp"].get<int>() < 1) fail(file, "reference \"spp\" must be a positive integer");
    r.spp = j["spp"].get<int>();
  }
  if (j.contains("seed")) r.seed = j["seed"].get<uint64_t>();
  if (j.contains("options")) {
    if (!j["options"].is_object()) fail(file, "reference \"options\" must be an object");
    flatten(j["options"], "", r.options, file);
    for (const auto& [k, v] : r.options) check_option(k, v, file);
  }
}

void parse_common(const json& j, Study& s, const std::string& file) {
  if (j.contains("base")) {
    if (!j["base"].is_object()) fail(file, "\"base\" must be an object of options");
    std::vector<std::pair<std::string, std::string>> b;
    flatten(j["base"], "", b, file);
    for (const auto& [k, v] : b) {
      check_option(k, v, file);
      auto it = std::find_if(s.base.begin(), s.base.end(), [&](const auto& p) { return p.first == k; });
      if (it != s.base.end()) it->second = v;
      else s.base.emplace_back(k, v);
    }
  }
  if (j.contains("axes")) parse_axes(j["axes"], s, file);
  if (j.contains("scenes")) {
    if (!j["scenes"].is_array() || j["scenes"].empty()) fail(file, "\"scenes\" must be a non-empty list of paths");
    s.scenes.clear();
    for (const auto& v : j["scenes"]) {
      if (!v.is_string()) fail(file, "\"scenes\" must hold paths (strings)");
      s.scenes.push_back(v.get<std::string>());
    }
  }
  if (j.contains("seeds")) parse_seeds(j["seeds"], s, file);
  if (j.contains("frames")) {
    if (!j["frames"].is_number_integer() || j["frames"].get<int>() < 1 || j["frames"].get<int>() > 100000)
      fail(file, "\"frames\" must be an integer in [1, 100000]");
    s.frames = j["frames"].get<int>();
  }
  if (j.contains("reference")) parse_reference(j["reference"], s.reference, file);
}

}  // namespace

const std::vector<std::string>& known_metrics() {
  static const std::vector<std::string> m = {"time", "mse", "relmse", "flip", "noise", "convergence", "relmse_reflective",
                                             "flip_reflective", "relmse_lowpass", "flicker", "cost"};
  return m;
}

bool Study::has_metric(const std::string& m) const { return std::find(metrics.begin(), metrics.end(), m) != metrics.end(); }

bool Study::needs_reference() const {
  return has_metric("mse") || has_metric("relmse") || has_metric("flip") || has_metric("convergence") ||
         has_metric("relmse_reflective") || has_metric("flip_reflective") || has_metric("relmse_lowpass");
}

std::vector<std::string> metric_columns(const Study& s) {
  std::vector<std::string> c = {"ms_median", "ms_iqr", "fps"};
  for (const char* m : {"mse", "relmse", "flip", "convergence", "noise", "relmse_reflective", "flip_reflective",
                        "relmse_lowpass", "flicker"})
    if (s.has_metric(m)) c.push_back(m);
  if (s.has_metric("relmse")) c.push_back("ref_relmse");  // the reference's own error (references.h)
  if (s.has_metric("cost"))  // rays per pixel by kind and the integrator's buffers per pixel (RunScorer::cost)
    for (const char* m : {"closest_px", "any_px", "rays_px", "bytes_px"}) c.push_back(m);
  return c;
}

namespace {
bool is_option_key(const std::string& k) {
  Options o;
  OptionPrinter pr;
  visit_options(o, pr);
  return std::any_of(pr.out.begin(), pr.out.end(), [&](const auto& kv) { return kv.first == k; });
}

// "a+b" keys of a plot's x / series / where: option keys, "frame", "scene" or "seed".
void check_plot_keys(const std::string& joined, const std::string& plot, const std::string& path) {
  for (const std::string& k : split_keys(joined))
    if (k != "frame" && k != "scene" && k != "seed" && !is_option_key(k))
      fail(path, fmt::format("plot '{}': '{}' is not an option key, \"frame\", \"scene\" or \"seed\"", plot, k));
}

// A "where" value as the result rows print it (option_values' text), so that 1.0 matches "1".
std::string where_value(const std::string& key, const json& v, const std::string& plot, const std::string& path) {
  const std::string text = value_text(v, path, "where." + key);
  if (key == "frame" || key == "scene" || key == "seed") return text;
  Options o;
  try {
    set_option(o, key, text);
  } catch (const OptionError& e) {
    fail(path, fmt::format("plot '{}': where '{}': {}", plot, key, e.what()));
  }
  for (const auto& [k, value] : option_values(o))
    if (k == key) return value;
  return text;
}

PlotSpec parse_plot(const json& p, const std::string& path, const std::vector<std::string>& cols) {
  check_keys(p, {"name", "title", "x", "y", "series", "logx", "logy", "where"}, path, "plot");
  PlotSpec ps;
  if (!p.contains("x") || !p.contains("y")) fail(path, "every plot needs \"x\" and \"y\"");
  ps.x = p["x"].get<std::string>();
  ps.y = p["y"].get<std::string>();
  if (p.contains("series")) ps.series = p["series"].get<std::string>();
  ps.logx = p.value("logx", false);
  ps.logy = p.value("logy", false);
  ps.name = p.value("name", ps.y + "-vs-" + ps.x);
  for (char& c : ps.name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '-';
  // A name starting with '-' reads as an option to gnuplot and the shell (the plot was silently lost).
  if (ps.name.empty() || ps.name[0] == '-')
    fail(path, fmt::format("plot name '{}' must start with a letter, digit or '_'", p.value("name", ps.name)));
  ps.title = p.value("title", ps.y + " vs " + ps.x);
  if (std::find(cols.begin(), cols.end(), ps.y) == cols.end())
    fail(path, fmt::format("plot '{}': y '{}' is not a metric column of this study", ps.name, ps.y));
  ps.x_metric = std::find(cols.begin(), cols.end(), ps.x) != cols.end();  // x a metric: the equal-time view
  if (!ps.x_metric) check_plot_keys(ps.x, ps.name, path);
  check_plot_keys(ps.series, ps.name, path);
  if (p.contains("where")) {
    if (!p["where"].is_object()) fail(path, fmt::format("plot '{}': \"where\" must be an object of key: value", ps.name));
    for (const auto& [k, v] : p["where"].items()) {
      check_plot_keys(k, ps.name, path);
      ps.where.emplace_back(k, where_value(k, v, ps.name, path));
    }
  }
  return ps;
}
}  // namespace

Study parse_study(const std::string& text, const std::string& path, bool quick) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::parse_error& e) {
    fail(path, std::string("invalid JSON: ") + e.what());
  }
  check_keys(j, {"name", "description", "base", "axes", "combine", "scenes", "seeds", "frames", "metrics", "reference",
                 "plots", "quick", "baseline"},
             path, "");
  Study s;
  s.file = path;
  s.dir = fs::absolute(fs::path(path)).parent_path().string();
  s.name = j.contains("name") ? j["name"].get<std::string>() : fs::path(path).stem().string();
  if (j.contains("description")) s.description = j["description"].get<std::string>();
  // --quick without a quick block would rerun the full study (or resume it) and stamp its report
  // "not evidence": refuse before anything is written.
  if (quick && !j.contains("quick")) fail(path, fmt::format("study '{}' has no quick block (--quick needs one)", s.name));
  s.seeds = {1};
  parse_common(j, s, path);
  if (j.contains("combine")) {
    std::string c = j["combine"].is_string() ? j["combine"].get<std::string>() : "";
    if (c != "grid" && c != "zip") fail(path, "\"combine\" must be \"grid\" or \"zip\"");
    s.zip = c == "zip";
  }
  if (j.contains("metrics")) {
    if (!j["metrics"].is_array()) fail(path, "\"metrics\" must be a list");
    for (const auto& m : j["metrics"]) {
      std::string name = m.is_string() ? m.get<std::string>() : "";
      const auto& km = known_metrics();
      if (std::find(km.begin(), km.end(), name) == km.end())
        fail(path, fmt::format("unknown metric '{}' (known: {})", m.dump(), fmt::join(km, ", ")));
      s.metrics.push_back(name);
    }
  } else {
    s.metrics = {"time", "relmse"};
  }
  if (j.contains("quick") && quick) {
    check_keys(j["quick"], {"base", "axes", "scenes", "seeds", "frames", "reference"}, path, "\"quick\"");
    parse_common(j["quick"], s, path);
  } else if (j.contains("quick")) {
    check_keys(j["quick"], {"base", "axes", "scenes", "seeds", "frames", "reference"}, path, "\"quick\"");
  }
  if (s.scenes.empty()) fail(path, "\"scenes\" is missing");
  if (s.zip)
    for (const auto& a : s.axes)
      if (a.values.size() != s.axes.front().values.size())
        fail(path, fmt::format("\"combine\": \"zip\" needs axes of equal length ('{}' has {}, '{}' has {})", a.key,
                               a.values.size(), s.axes.front().key, s.axes.front().values.size()));
  for (const auto& sc : s.scenes) {
    std::string p = resolve_path(sc, s.dir);
    if (!fs::exists(p)) fail(path, fmt::format("scene '{}' not found (relative to {} or the repository root)", sc, s.dir));
    s.scene_paths.push_back(p);
  }
  if (j.contains("baseline")) {
    if (!j["baseline"].is_object() || j["baseline"].empty()) fail(path, "\"baseline\" must be an object of key: value");
    for (const auto& [k, v] : j["baseline"].items()) {
      check_plot_keys(k, "baseline", path);
      s.baseline.emplace_back(k, where_value(k, v, "baseline", path));
    }
  }
  // Plots.
  if (j.contains("plots")) {
    if (!j["plots"].is_array()) fail(path, "\"plots\" must be a list");
    std::set<std::string> names;
    for (const auto& p : j["plots"]) {
      PlotSpec ps = parse_plot(p, path, metric_columns(s));
      if (!names.insert(ps.name).second) fail(path, fmt::format("two plots named '{}'", ps.name));
      s.plots.push_back(ps);
    }
  }
  return s;
}

Study load_study(const std::string& path, bool quick) {
  std::ifstream in(path);
  if (!in) throw StudyError(path + ": cannot open study file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_study(ss.str(), path, quick);
}

void apply_study_sets(Study& s, const std::vector<std::string>& sets) {
  for (const std::string& kv : sets) {
    const size_t eq = kv.find('=');
    if (eq == std::string::npos || eq == 0) throw StudyError("--set '" + kv + "': expected KEY=VALUE");
    const std::string k = kv.substr(0, eq), v = kv.substr(eq + 1);
    try {
      Options trial;
      set_option(trial, k, v);
    } catch (const OptionError& e) {
      throw StudyError(std::string("--set: ") + e.what());
    }
    auto it = std::find_if(s.base.begin(), s.base.end(), [&](const auto& p) { return p.first == k; });
    if (it != s.base.end()) it->second = v;
    else s.base.emplace_back(k, v);
  }
}

std::vector<Configuration> expand(const Study& s) {
  std::vector<Configuration> out;
  if (s.axes.empty()) return {Configuration{}};
  if (s.zip) {
    for (size_t i = 0; i < s.axes.front().values.size(); ++i) {
      Configuration c;
      for (const auto& a : s.axes)
        if (a.values[i]) c.values.emplace_back(a.key, *a.values[i]);
      out.push_back(std::move(c));
    }
    return out;
  }
  std::vector<size_t> idx(s.axes.size(), 0);
  for (;;) {
    Configuration c;
    for (size_t a = 0; a < s.axes.size(); ++a)
      if (s.axes[a].values[idx[a]]) c.values.emplace_back(s.axes[a].key, *s.axes[a].values[idx[a]]);
    out.push_back(std::move(c));
    size_t a = s.axes.size();
    while (a > 0) {
      --a;
      if (++idx[a] < s.axes[a].values.size()) break;
      idx[a] = 0;
      if (a == 0) return out;
    }
  }
}

Options make_options(const Study& s, const Options& scene_defaults, const Configuration& c, uint64_t seed) {
  Options o = scene_defaults;
  auto set = [&](const std::string& k, const std::string& v) {
    if (k == "render.camera_path" && !v.empty()) set_option(o, k, resolve_path(v, s.dir));
    else set_option(o, k, v);
  };
  for (const auto& [k, v] : s.base) set(k, v);
  for (const auto& [k, v] : c.values) set(k, v);
  set_option(o, "render.frames", std::to_string(s.frames));
  set_option(o, "render.seed", std::to_string(seed));
  validate_options(o);
  return o;
}

std::string non_default_options(const Options& o) {
  static const auto defaults = option_values(Options{});
  std::string text;
  for (const auto& [k, v] : option_values(o)) {
    auto it = std::find_if(defaults.begin(), defaults.end(), [&](const auto& d) { return d.first == k; });
    if (it == defaults.end() || it->second != v) text += k + "=" + v + "\n";
  }
  return text;
}

std::string repository_root() {
  auto good = [](const fs::path& p) { return fs::is_directory(p / "studies") && fs::is_directory(p / "scenes"); };
#ifdef RESTIR_SOURCE_DIR
  if (good(RESTIR_SOURCE_DIR)) return fs::path(RESTIR_SOURCE_DIR).lexically_normal().string();
#endif
  // This file is compiled by absolute path: <root>/src/study/study_file.cpp.
  fs::path here = fs::path(__FILE__).parent_path().parent_path().parent_path();
  if (here.is_absolute() && good(here)) return here.lexically_normal().string();
  char buf[4096];
  ssize_t n = readlink("/proc/self/exe", buf, sizeof(buf) - 1);
  if (n > 0) {
    fs::path p = fs::path(std::string(buf, size_t(n))).parent_path();
    for (; !p.empty() && p != p.root_path(); p = p.parent_path())
      if (good(p)) return p.string();
  }
  return "";
}

std::string resolve_path(const std::string& p, const std::string& study_dir) {
  fs::path path(p);
  if (path.is_absolute()) return p;
  if (!study_dir.empty() && fs::exists(fs::path(study_dir) / path)) return (fs::path(study_dir) / path).lexically_normal().string();
  std::string root = repository_root();
  if (!root.empty()) return (fs::path(root) / path).lexically_normal().string();
  return p;
}

std::string find_study(const std::string& name) {
  if (fs::is_regular_file(name)) return name;
  std::string root = repository_root();
  if (!root.empty()) {
    fs::path p = fs::path(root) / "studies" / (name + ".json");
    if (fs::is_regular_file(p)) return p.string();
  }
  throw StudyError(fmt::format("study '{}' not found: not a file, and no {}/studies/{}.json (`restir study --list`)", name,
                               root.empty() ? "<repository>" : root, name));
}

std::vector<std::pair<std::string, std::string>> list_studies() {
  std::vector<std::pair<std::string, std::string>> out;
  std::string root = repository_root();
  if (root.empty()) return out;
  for (const auto& e : fs::directory_iterator(fs::path(root) / "studies")) {
    if (e.path().extension() != ".json") continue;
    try {
      Study s = load_study(e.path().string(), false);
      out.emplace_back(e.path().stem().string(), s.description);
    } catch (const std::exception& ex) {
      out.emplace_back(e.path().stem().string(), std::string("(invalid: ") + ex.what() + ")");
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace rl::study
