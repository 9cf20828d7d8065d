#include "study/results.h"

#include <algorithm>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/build_info.h"
#include "image/image_io.h"
#include "study/study_file.h"

namespace rl::study {
namespace fs = std::filesystem;
using nlohmann::ordered_json;

std::string Row::option(const std::string& key) const {
  if (auto plus = key.find('+'); plus != std::string::npos)  // "a+b": both values, for series keys
    return option(key.substr(0, plus)) + " " + option(key.substr(plus + 1));
  if (key == "scene") return scene;
  if (key == "seed") return std::to_string(seed);
  if (key == "frame") return std::to_string(frame);
  for (const auto& [k, v] : options)
    if (k == key) return v;
  return "";
}

bool Row::matches(const std::vector<std::pair<std::string, std::string>>& where) const {
  return std::all_of(where.begin(), where.end(), [&](const auto& kv) { return option(kv.first) == kv.second; });
}

std::vector<std::string> split_keys(const std::string& joined) {
  std::vector<std::string> keys;
  size_t start = 0;
  for (size_t plus; (plus = joined.find('+', start)) != std::string::npos; start = plus + 1)
    keys.push_back(joined.substr(start, plus - start));
  if (start < joined.size()) keys.push_back(joined.substr(start));  // as getline: "" and a final '+' add nothing
  return keys;
}

double Row::metric(const std::string& name) const {
  auto it = metrics.find(name);
  return it == metrics.end() ? kNone : it->second;
}

std::string hash_hex(const std::string& text) {
  uint64_t h = 14695981039346656037ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return fmt::format("{:016x}", h);
}

Stat stat_of(const std::vector<double>& v) {
  Stat s;
  double sum = 0;
  for (double x : v)
    if (std::isfinite(x)) sum += x, ++s.n;
  if (s.n == 0) return s;
  s.mean = sum / s.n;
  if (s.n > 1) {
    double ss = 0;
    for (double x : v)
      if (std::isfinite(x)) ss += (x - s.mean) * (x - s.mean);
    s.stderr_ = std::sqrt(ss / (s.n - 1)) / std::sqrt(double(s.n));
  }
  return s;
}

ResultStore::ResultStore(std::string dir, std::string study, std::vector<std::string> metric_columns)
    : dir_(std::move(dir)), study_(std::move(study)), columns_(std::move(metric_columns)) {}

void ResultStore::load() {
  std::lock_guard lock(mutex_);
  rows_.clear();
  fs::path p = fs::path(dir_) / "results.json";
  if (!fs::exists(p)) return;
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  ordered_json j;
  try {
    j = ordered_json::parse(ss.str());
  } catch (const std::exception& e) {
    throw StudyError(p.string() + ": unreadable results (" + e.what() + "); move it away to start over");
  }
  for (const auto& r : j.at("rows")) {
    Row row;
    row.id = r.at("id").get<std::string>();
    row.config = r.at("config").get<std::string>();
    row.scene = r.at("scene").get<std::string>();
    row.seed = r.at("seed").get<uint64_t>();
    row.frame = r.at("frame").get<int>();
    for (const auto& [k, v] : r.at("options").items()) row.options.emplace_back(k, v.get<std::string>());
    for (const auto& [k, v] : r.at("metrics").items()) row.metrics[k] = v.is_null() ? kNone : v.get<double>();
    rows_.push_back(std::move(row));
  }
}

bool ResultStore::has(const std::string& id) const {
  std::lock_guard lock(mutex_);
  for (const auto& r : rows_)
    if (r.id == id) return true;
  return false;
}

void ResultStore::append(const std::vector<Row>& rows) {
  std::lock_guard lock(mutex_);
  rows_.insert(rows_.end(), rows.begin(), rows.end());
  write_locked();
}

void ResultStore::replace(std::vector<Row> rows) {
  std::lock_guard lock(mutex_);
  rows_ = std::move(rows);
  write_locked();
}

std::vector<Row> ResultStore::rows() const {
  std::lock_guard lock(mutex_);
  return rows_;
}

size_t ResultStore::size() const {
  std::lock_guard lock(mutex_);
  return rows_.size();
}

void ResultStore::write_locked() const {
  ordered_json j;
  j["study"] = study_;
  j["version"] = build_id();
  j["metrics"] = columns_;
  ordered_json rows = ordered_json::array();
  for (const auto& r : rows_) {
    ordered_json o;
    o["id"] = r.id;
    o["config"] = r.config;
    o["scene"] = r.scene;
    o["seed"] = r.seed;
    o["frame"] = r.frame;
    ordered_json opts = ordered_json::object();
    for (const auto& [k, v] : r.options) opts[k] = v;
    o["options"] = opts;
    ordered_json m = ordered_json::object();
    for (const auto& c : columns_) {
      double v = r.metric(c);
      if (std::isfinite(v)) m[c] = v;
      else m[c] = nullptr;
    }
    o["metrics"] = m;
    rows.push_back(o);
  }
  j["rows"] = rows;
  // JSON first (the resume store), then the CSV view of the same rows.
  write_text_file_atomic((fs::path(dir_) / "results.json").string(), j.dump(1) + "\n");
  write_text_file_atomic((fs::path(dir_) / "results.csv").string(), rows_to_csv(rows_, columns_));
}

namespace {
std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string o = "\"";
  for (char c : s) o += c == '"' ? std::string("\"\"") : std::string(1, c);
  return o + "\"";
}
}  // namespace

std::string rows_to_csv(const std::vector<Row>& rows, const std::vector<std::string>& metric_columns) {
  // Option columns: the union over rows in first-seen order (all rows share option_values()).
  std::vector<std::string> keys;
  std::set<std::string> seen;
  for (const auto& r : rows)
    for (const auto& [k, v] : r.options)
      if (seen.insert(k).second) keys.push_back(k);
  std::string out = "id,config,scene,seed,frame";
  for (const auto& k : keys) out.append(",").append(csv_field(k));
  for (const auto& m : metric_columns) out.append(",").append(m);
  out += "\n";
  for (const auto& r : rows) {
    out += fmt::format("{},{},{},{},{}", r.id, r.config, csv_field(r.scene), r.seed, r.frame);
    for (const auto& k : keys) out.append(",").append(csv_field(r.option(k)));
    for (const auto& m : metric_columns) {
      double v = r.metric(m);
      out += std::isfinite(v) ? fmt::format(",{:.9g}", v) : std::string(",");
    }
    out += "\n";
  }
  return out;
}

}  // namespace rl::study
