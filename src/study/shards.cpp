#include "study/shards.h"

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <set>
#include <utility>

#include "study/study_file.h"

namespace rl::study {
namespace fs = std::filesystem;

ShardSpec parse_shard(const std::string& text) {
  ShardSpec s;
  const auto slash = text.find('/');
  auto number = [&](std::string_view v, int& out) {
    auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), out);
    return ec == std::errc() && end == v.data() + v.size() && !v.empty();
  };
  if (slash == std::string::npos || !number(std::string_view(text).substr(0, slash), s.index) ||
      !number(std::string_view(text).substr(slash + 1), s.count) || s.count < 1 || s.index < 0 || s.index >= s.count)
    throw StudyError("--shard '" + text + "': expected I/N with 0 <= I < N (e.g. 0/4 for the first of four shards)");
  return s;
}

std::string shard_dir(const std::string& out, const ShardSpec& shard) {
  return (fs::path(out) / "shards" / (std::to_string(shard.index) + "-of-" + std::to_string(shard.count))).string();
}

std::vector<Row> load_shard_rows(const std::string& out, const std::vector<std::string>& metric_columns,
                                 const std::string& study) {
  const fs::path root = fs::path(out) / "shards";
  std::vector<fs::path> dirs;
  if (fs::is_directory(root))
    for (const auto& e : fs::directory_iterator(root))
      if (e.is_directory()) dirs.push_back(e.path());
  std::sort(dirs.begin(), dirs.end());
  std::vector<Row> rows;
  for (const fs::path& d : dirs) {
    ResultStore part(d.string(), study, metric_columns);
    part.load();
    rows = union_rows(std::move(rows), part.rows());
  }
  return rows;
}

std::vector<Row> union_rows(std::vector<Row> a, const std::vector<Row>& b) {
  std::set<std::pair<std::string, int>> have;
  for (const Row& r : a) have.insert({r.id, r.frame});
  for (const Row& r : b)
    if (have.insert({r.id, r.frame}).second) a.push_back(r);
  return a;
}

}  // namespace rl::study
