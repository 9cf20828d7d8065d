// Helpers of the study tests (tests/study/): a fresh folder, a file written, a study JSON around
// some fields, and results.csv read back.
#pragma once
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "test_helpers.h"

namespace rl::test::study_files {

namespace fs = std::filesystem;

inline fs::path temp_dir(const std::string& name) { return test::fresh_temp_dir("study-" + name); }
inline void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }
inline std::string cbox() { return test::own_scene("cornell-box.pbrt"); }

// A study JSON around the given body fields (scenes default to the Cornell box, absolute path).
inline std::string study_json(const std::string& body) {
  return "{\"scenes\": [\"" + cbox() + "\"]" + (body.empty() ? "" : ", " + body) + "}";
}

struct CsvTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;  // simple split on ',' (the test studies quote nothing)
  int col(const std::string& name) const {
    for (size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return int(i);
    return -1;
  }
};
inline CsvTable read_csv(const fs::path& p) {
  CsvTable t;
  std::istringstream in(test::read_file(p));
  std::string line;
  bool first = true;
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::string cur;
    for (char c : line) {
      if (c == ',') f.push_back(cur), cur.clear();
      else cur += c;
    }
    f.push_back(cur);
    if (first) t.header = f, first = false;
    else t.rows.push_back(f);
  }
  return t;
}

}  // namespace rl::test::study_files
