// Result rows of a study: one per (configuration, scene, seed), or per frame for over-time
// studies. results.json is the store the runner resumes from; results.csv is the same table.
// Both are rewritten whole (temp file + rename) after every finished job, under a lock, so an
// interrupted study never leaves a partial row.
#pragma once
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace rl::study {

constexpr double kNone = std::numeric_limits<double>::quiet_NaN();

struct Row {
  std::string id;      // hash of (full option set incl. seed, scene): the resume key
  std::string config;  // hash of (option set without the seed, scene): groups seeds
  std::string scene;   // as written in the study file
  uint64_t seed = 0;
  int frame = 0;       // frame index (per-frame studies) or the last frame
  std::vector<std::pair<std::string, std::string>> options;  // option_values(), every key
  std::map<std::string, double> metrics;                     // NaN = not computed

  // "scene", "seed", "frame" or an option key; "a+b" joins the values of a and b with a space.
  std::string option(const std::string& key) const;
  double metric(const std::string& name) const;
  // True when option(key) == value for every pair (a plot's "where", a study's "baseline").
  bool matches(const std::vector<std::pair<std::string, std::string>>& where) const;
};

// The keys of "a+b" (plot x / series / where keys): {"a", "b"}; "" gives none.
std::vector<std::string> split_keys(const std::string& joined);

class ResultStore {
 public:
  ResultStore(std::string dir, std::string study, std::vector<std::string> metric_columns);
  // Reads DIR/results.json if present (rows of earlier, possibly interrupted runs); a file that is
  // not JSON is a StudyError.
  void load();
  bool has(const std::string& id) const;
  // Adds the rows of one finished job and rewrites results.json and results.csv atomically.
  void append(const std::vector<Row>& rows);
  // Replaces every row (final pass: noise filled in, sorted) and rewrites the files.
  void replace(std::vector<Row> rows);
  std::vector<Row> rows() const;
  size_t size() const;

 private:
  void write_locked() const;
  std::string dir_, study_;
  std::vector<std::string> columns_;
  std::vector<Row> rows_;
  mutable std::mutex mutex_;
};

std::string rows_to_csv(const std::vector<Row>& rows, const std::vector<std::string>& metric_columns);

// Mean and standard error of the finite values (stderr = sd / sqrt(n), 0 for n < 2).
struct Stat {
  double mean = kNone, stderr_ = 0;
  int n = 0;
};
Stat stat_of(const std::vector<double>& v);

// 64-bit FNV-1a as 16 hex digits.
std::string hash_hex(const std::string& text);

}  // namespace rl::study
