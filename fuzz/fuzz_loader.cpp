// libFuzzer target for the scene loaders: the input is written to a temp file with the extension
// FUZZ_EXT (pbrt, ply, obj, gltf) and loaded with rl::load_scene. A SceneError (or any
// std::exception: a clean, one-line refusal) is the expected outcome of garbage; a crash, a
// sanitizer report, a hang or a leak is a bug. Built by scripts/fuzz.sh (clang, -fsanitize=fuzzer).
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <exception>
#include <fstream>
#include <string>

#include "scene/loader.h"


extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > (1 << 20)) return 0;
  static const std::string path = "/tmp/restir-fuzz-" + std::to_string(::getpid()) + "." FUZZ_EXT;
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  }
  try {
    rl::Scene s = rl::load_scene(path);
    (void)s;
  } catch (const std::exception&) {
  }
  return 0;
}
