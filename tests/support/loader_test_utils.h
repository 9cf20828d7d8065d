// Helpers shared by the loader tests: temp files, small scenes, resolved normals.
#pragma once
#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <system_error>
#include <unistd.h>
#include <vector>

#include "image/image_io.h"
#include "scene/loader.h"
#include "scene/pbrt_tokenizer.h"
#include "scene/ply.h"

namespace rl::loader_test {
namespace fs = std::filesystem;


// The directories temp_dir() made, removed when the test process exits: every loader test run
// used to leave its files behind in /tmp (a thousand directories after a few dozen runs).
struct TempDirs {
  std::mutex mutex;
  std::vector<fs::path> made;
  ~TempDirs() {
    for (const fs::path& d : made) {
      std::error_code ec;
      fs::remove_all(d, ec);
    }
  }
};

inline fs::path temp_dir() {
  static TempDirs dirs;
  static std::atomic<int> counter{0};
  fs::path d = fs::temp_directory_path() /
               ("restir_loaders_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  fs::create_directories(d);
  std::lock_guard<std::mutex> lock(dirs.mutex);
  dirs.made.push_back(d);
  return d;
}

inline std::string write_file(const fs::path& p, const std::string& text) {
  std::ofstream f(p, std::ios::binary);
  f << text;
  return p.string();
}

// Loads a pbrt scene given as text (written to a temp file named `name`).
inline Scene load_text(const std::string& text, const std::string& name = "t.pbrt") {
  fs::path d = temp_dir();
  return load_scene(write_file(d / name, text));
}

// The SceneError message for a bad pbrt text; fails the test if no SceneError is thrown.
inline std::string error_of(const std::string& text, const std::string& name = "bad.pbrt") {
  fs::path d = temp_dir();
  std::string path = write_file(d / name, text);
  try {
    load_scene(path);
  } catch (const SceneError& e) {
    std::string w = e.what();
    CHECK(w.find('\n') == std::string::npos);
    return w;
  } catch (const std::exception& e) {
    FAIL("not a SceneError: " << e.what());
  }
  FAIL("no error for:\n" << text);
  return "";
}

inline Vec3 resolved_normal(const TriangleMesh& m, size_t t) {
  Vec3 p0 = m.positions[m.indices[3 * t]], p1 = m.positions[m.indices[3 * t + 1]], p2 = m.positions[m.indices[3 * t + 2]];
  Vec3 n = normalize(cross(p1 - p0, p2 - p0));
  return m.flip_normal ? -n : n;
}

inline bool near(Vec3 a, Vec3 b, float eps = 1e-3f) { return length(a - b) <= eps; }

inline Mat4 world_from_camera(const CameraKey& k) {
  Mat4 w;
  REQUIRE(k.camera_from_world.inverse(w));
  return w;
}

const std::string kWorld = "Camera \"perspective\"\nWorldBegin\n";


}  // namespace rl::loader_test
