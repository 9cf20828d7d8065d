// Study files: a JSON description of a parameter sweep (format documented in studies/README.md).
// Parsing validates everything up front (unknown keys, option keys and values, paths), so that a
// typo fails before any rendering; expansion turns the axes into the list of configurations.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "frame/options.h"

namespace rl::study {

// Thrown for any problem with a study file; what() is one line naming the file and the key.
struct StudyError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// One sweep axis: an option key and its values (as text, parsed by set_option).
struct Axis {
  std::string key;
  // A value per configuration; null (JSON null in "values") leaves the key unset there: the key of
  // a zipped axis that only some of its integrators read (check_option_groups).
  std::vector<std::optional<std::string>> values;
};

struct PlotSpec {
  std::string name;    // file stem under plots/
  std::string title;
  std::string x;       // option key, "frame", "scene" or "seed"; or a metric column (x_metric)
  std::string y;       // metric name (see kMetricColumns)
  std::string series;  // option key or "scene" (one line per value); empty = one line
  bool logx = false, logy = false;
  // x is a metric (e.g. ms_median: error against time, the equal-time view): one point per
  // configuration and scene, at the mean of both metrics over its seeds.
  bool x_metric = false;
  std::vector<std::pair<std::string, std::string>> where;  // only rows whose option(key) == value
};

struct ReferenceSpec {
  int spp = 1024;
  uint64_t seed = 7777;
  std::vector<std::pair<std::string, std::string>> options;  // extra key=value for the reference
};

struct Study {
  std::string name, description, file, dir;  // dir: folder of the study file
  std::vector<std::pair<std::string, std::string>> base;  // key, value text (in file order)
  std::vector<Axis> axes;
  bool zip = false;                      // "combine": "zip" (else "grid")
  std::vector<std::string> scenes;       // as written in the file
  std::vector<std::string> scene_paths;  // resolved
  std::vector<uint64_t> seeds;
  int frames = 1;
  std::vector<std::string> metrics;  // requested: time, mse, relmse, flip, noise, convergence
  ReferenceSpec reference;
  std::vector<PlotSpec> plots;
  // "baseline": {key: value, ...}: the configurations everything else is compared with (e.g. the
  // path tracer); legends mark them and the report's table gives each metric relative to them.
  std::vector<std::pair<std::string, std::string>> baseline;

  bool has_metric(const std::string& m) const;
  bool per_frame() const { return has_metric("convergence"); }  // one row per frame
  bool needs_reference() const;
};

// One configuration of the sweep: the axis values (key, value text) applied over the base.
struct Configuration {
  std::vector<std::pair<std::string, std::string>> values;
};

// The metric names a study may request and the CSV columns they produce.
const std::vector<std::string>& known_metrics();
std::vector<std::string> metric_columns(const Study& s);

// Parses a study file; quick = apply its "quick" block. Throws StudyError.
Study load_study(const std::string& path, bool quick);
// Each "key=value" of `sets` over s.base (replacing the key's value, or added after the others),
// checked as the base is: an unknown key or a bad value is a StudyError naming --set.
void apply_study_sets(Study& s, const std::vector<std::string>& sets);
Study parse_study(const std::string& json_text, const std::string& path, bool quick);

// grid: cartesian product (first axis varies slowest); zip: i-th values together (equal lengths).
std::vector<Configuration> expand(const Study& s);

// Options for one (scene hints, configuration, seed): defaults < scene < base < axes < frames/seed.
// Relative camera paths are resolved like scenes.
Options make_options(const Study& s, const Options& scene_defaults, const Configuration& c, uint64_t seed);

// "key=value\n" for every option that differs from its default: the stable identity of an option
// set (options added to the renderer later, at their defaults, do not change it).
std::string non_default_options(const Options& o);

// The repository root (the folder holding studies/ and scenes/): found from the compiled source
// path, then from the executable's folder upwards. Empty if none.
std::string repository_root();
// A path written in a study: absolute as is; else relative to the study file's folder if it exists
// there, else relative to the repository root.
std::string resolve_path(const std::string& p, const std::string& study_dir);
// "NAME" -> <root>/studies/NAME.json unless NAME is an existing file. Throws StudyError.
std::string find_study(const std::string& name_or_path);
// Built-in studies: (name, description), sorted by name.
std::vector<std::pair<std::string, std::string>> list_studies();

}  // namespace rl::study
