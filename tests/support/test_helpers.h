// Helpers shared by the integration tests: scene paths, small renders, running the CLI.
#pragma once
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>

#include "image/image.h"
#include "frame/integrator.h"
#include "frame/options.h"
#include "frame/render.h"
#include "scene/loader.h"

namespace rl::test {

// The build's paths, unless the environment moves them (scripts/gpu-check.sh runs the GPU tests
// from a bundle on another machine: RESTIR_SHARED_DIR, RESTIR_SOURCE_DIR).
inline std::string env_or(const char* name, const char* fallback) {
  const char* v = std::getenv(name);
  return v && *v ? v : fallback;
}
inline std::string shared_scene(const std::string& rel) { return env_or("RESTIR_SHARED_DIR", RESTIR_SHARED_DIR) + "/scenes/" + rel; }
inline std::string own_scene(const std::string& rel) { return env_or("RESTIR_SOURCE_DIR", RESTIR_SOURCE_DIR) + "/scenes/" + rel; }

// An empty folder of the system's temp directory, "restir-NAME-PID", made afresh (a leftover of
// an earlier run is removed first): one per test case, so cases and concurrent runs do not meet.
inline std::filesystem::path fresh_temp_dir(const std::string& name) {
  namespace fs = std::filesystem;
  fs::path d = fs::temp_directory_path() / ("restir-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// The whole file's bytes (empty if it cannot be read).
inline std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Options = defaults < scene hints < the given key=value settings.
inline Options options_for(const Scene& scene, std::initializer_list<const char*> sets) {
  Options o;
  apply_scene_hints(o, scene.hints);
  for (const char* s : sets) set_option_assignment(o, s);
  return o;
}

inline double mean_channel(const Image& img, int c) {
  double s = 0;
  for (const Rgb& p : img.pixels) s += p[c];
  return s / double(img.size());
}

struct CommandResult {
  int status = -1;
  std::string output;  // stdout + stderr
};

// Runs the restir binary with the given argument string (shell syntax).
inline CommandResult run_restir(const std::string& args) {
  CommandResult r;
  std::string cmd = std::string(RESTIR_BIN) + " " + args + " 2>&1";
  FILE* f = popen(cmd.c_str(), "r");
  if (!f) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), f)) > 0) r.output.append(buf.data(), n);
  int st = pclose(f);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

// For tests that share one Options between integrators (a loop over them): the keys set explicitly
// narrowed to the groups o.integrator reads (check_option_groups), as if each had been set only
// where it is read. The values stay; only their record as explicit goes.
inline Options only_read_keys(Options o) {
  const IntegratorInfo& info = find_integrator(o.integrator);
  std::erase_if(o.explicit_keys, [&](const std::string& k) {
    const size_t dot = k.find('.');
    if (dot == std::string::npos) return false;
    const std::string group = k.substr(0, dot);
    return group != "film" && group != "render" && group != "output" && !info.reads_group(group);
  });
  return o;
}

}  // namespace rl::test
