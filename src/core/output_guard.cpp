#include "core/output_guard.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <stdexcept>

namespace rl {
namespace fs = std::filesystem;

namespace {

std::string lower_ext(const std::string& path) {
  std::string e = fs::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return e;
}

[[noreturn]] void refuse(const OutputFile& o, const std::string& why) {
  throw IoError(o.flag + " '" + o.path + "': " + why);
}

void check_extension(const OutputFile& o) {
  if (o.directory || o.extensions.empty()) return;
  const std::string e = lower_ext(o.path);
  if (std::find(o.extensions.begin(), o.extensions.end(), e) != o.extensions.end()) return;
  std::string want;
  for (const auto& x : o.extensions) want += (want.empty() ? "" : " or ") + x;
  refuse(o, "the extension '" + e + "' does not match the format written (" + want + ")");
}

fs::path output_folder(const OutputFile& o) {
  if (o.directory) return fs::path(o.path);
  fs::path parent = fs::path(o.path).parent_path();
  return parent.empty() ? fs::path(".") : parent;
}

}  // namespace

bool same_file(const std::string& a, const std::string& b) {
  std::error_code ea, eb;
  if (fs::exists(a, ea) && fs::exists(b, eb)) {
    std::error_code ec;
    bool eq = fs::equivalent(a, b, ec);
    if (!ec) return eq;
  }
  std::error_code e1, e2;
  fs::path pa = fs::weakly_canonical(fs::absolute(a), e1), pb = fs::weakly_canonical(fs::absolute(b), e2);
  if (e1 || e2) return fs::absolute(a).lexically_normal() == fs::absolute(b).lexically_normal();
  return pa == pb;
}

bool replaceable_sidecar(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(path, ec))) return true;
  if (!fs::is_regular_file(path, ec)) return false;
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  nlohmann::json j = nlohmann::json::parse(ss.str(), nullptr, false);
  if (j.is_discarded() || !j.is_object()) return false;
  if (j.contains(kSidecarMarker)) return true;
  std::set<std::string> keys;
  for (auto it = j.begin(); it != j.end(); ++it) keys.insert(it.key());
  return keys == std::set<std::string>{"version", "scene", "config", "frame_ms"};  // sidecars before the marker
}

void check_outputs(const std::vector<OutputFile>& outputs, const std::vector<std::string>& inputs) {
  for (size_t i = 0; i < outputs.size(); ++i) {
    const OutputFile& o = outputs[i];
    if (o.path.empty()) refuse(o, "empty path");
    for (const std::string& in : inputs)
      if (same_file(o.path, in)) refuse(o, "refusing to overwrite an input of this command ('" + in + "')");
    for (size_t j = 0; j < i; ++j)
      if (same_file(o.path, outputs[j].path))
        refuse(o, "the same file is also the output of " + outputs[j].flag + "; give each output its own path");
    check_extension(o);
    std::error_code ec;
    fs::file_status st = fs::status(o.path, ec);
    if (!o.directory && fs::is_directory(st)) refuse(o, "is a directory");
    if (o.directory && fs::exists(st) && !fs::is_directory(st)) refuse(o, "exists and is not a directory");
    if (o.sidecar && !replaceable_sidecar(o.path))
      refuse(o, "would replace an existing file that is not a restir sidecar; move that file or choose another output name");
  }
  // Only after every check passed: create the folders, so a refused command leaves nothing behind.
  for (const OutputFile& o : outputs) {
    fs::path dir = output_folder(o);
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) {
      fs::create_directories(dir, ec);
      if (ec) refuse(o, "cannot create the folder '" + dir.string() + "': " + ec.message());
    }
    if (::access(dir.c_str(), W_OK) != 0) refuse(o, "the folder '" + dir.string() + "' is not writable");
  }
}

}  // namespace rl
