// The viewer's script mode (`restir view SCENE --script FILE`): a list of commands the viewer runs
// in order instead of waiting for the user, so that a test (or a study preparation) can drive the
// GUI deterministically. One command a line; '#' starts a comment.
//   set KEY VALUE        change an option, as if edited in the panel (VALUE: rest of the line)
//   frames N             render N more frames
//   screenshot PATH      PATH.exr (HDR frame), PATH.png (view as shown), PATH.json (sidecar),
//                        PATH.window.png (the whole window); a .exr/.png extension is dropped
//   view NAME            radiance | error | split
//   split F              A/B split position in [0, 1] (left: the render, right: the reference)
//   accumulate on|off    progressive mean over frames, or each frame's raw output
//   scale S              render scale: 1, 0.5 or 0.25 of the film size
//   camera orbit DYAW DPITCH | camera move DX DY DZ | camera reset | camera mode orbit|fly
//   record start | record stop | record save PATH     camera path (render.camera_path format)
//   reference on [SPP]   render the background reference (pt) beside the frames, to SPP samples
//                        per pixel (default 4096); reference off | reference wait (until it has them)
//   save-config PATH     the current options as a --config JSON file
//   quit                 close the viewer (the end of the script does too)
#pragma once
#include <stdexcept>
#include <string>
#include <vector>

namespace rl::viewer {

// A viewer script that cannot be read, parsed or run to its end: "FILE:LINE: message".
struct ScriptError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct ScriptCommand {
  std::string verb;               // "set", "frames", ...
  std::vector<std::string> args;  // set: {key, value}; the others: their words
  int line = 0;                   // 1-based line in the script file
};

struct Script {
  std::string path;
  std::vector<ScriptCommand> commands;
  // "error: "-less text naming the file and line: "FILE:LINE: message".
  std::string where(const ScriptCommand& c) const { return path + ":" + std::to_string(c.line); }
};

// Parses script text; throws ScriptError "PATH:LINE: ..." for an unknown command or a wrong number
// or form of arguments (option keys and values are checked when the command runs).
Script parse_script(const std::string& text, const std::string& path);
// Reads and parses a script file (a missing file is a ScriptError naming it).
Script load_script(const std::string& path);

// Number parsing shared by the script and the panels: the whole word must be the number.
bool parse_int(const std::string& word, int& out);
bool parse_float(const std::string& word, float& out);

}  // namespace rl::viewer
