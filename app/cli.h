// What the `restir` subcommands share: how an error in the call is told from bad input, and each
// command's arguments and entry point (app/main.cpp wires them to CLI11).
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace rl::cli {

// A mistake in how the command was called (exit status 2), as opposed to bad input (1).
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// CLI11's own range validators print DBL_MAX in full and say "0 not in range 0.000000 to ...".
CLI::Validator integer_in(int64_t lo, int64_t hi);

// The text on one line (an error message from a library may hold newlines).
std::string one_line(std::string s);

struct RenderArgs {
  std::string scene, out, png, average, frame_dir, timings, config;
  std::string integrator, res, tonemap;
  int spp = 0, frames = 0, threads = -1;
  int64_t seed = -1;
  std::vector<std::string> sets;
  bool quiet = false;
  std::string frame_format = "exr";  // --frame-dir: exr, png or both
  std::string aov_dir;               // --aov-dir: DIR/aov_NNNN.exr, one multi-channel EXR per frame
  bool stats = false;                // --stats: per-stage summary on stdout
};

// render: the scene to EXR/PNG (app/render_command.cpp).
int run_render(const RenderArgs& a);

struct ExportArgs {
  std::string scene, out, config;
  std::vector<std::string> sets;
};
int run_export_mitsuba(const ExportArgs& a);
int run_info(const std::string& path);

struct CompareArgs {
  std::string test, reference;
  std::string error_map;  // --error-map OUT.png
  std::string crop;       // --crop X,Y,W,H
  bool json = false;
};
// compare: metrics of TEST against REFERENCE (app/image_commands.cpp).
int run_compare(const CompareArgs& a);

struct TonemapArgs {
  std::string in, out;
  std::vector<std::string> sets;  // output.* only
};
// tonemap: an EXR (or HDR) to a display-ready PNG, with the tone mapping it was rendered with.
int run_tonemap(const TonemapArgs& a);

}  // namespace rl::cli
