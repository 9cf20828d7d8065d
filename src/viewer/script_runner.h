// Runs a viewer script (script.h) against a Session: option changes, frames, camera moves,
// screenshots. The GUI calls step() once per drawn frame, so the window keeps drawing while the
// worker renders; a test can drive the same runner without a window.
#pragma once
#include <functional>
#include <string>

#include "viewer/display.h"
#include "viewer/script.h"
#include "viewer/session.h"

namespace rl::viewer {

class ScriptRunner {
 public:
  enum class Step {
    waiting,  // frames (or the background reference) are rendering: call again after drawing
    drawn,    // ran a screenshot: draw one frame (and capture the window) before the next step
    done,     // the script ended or said quit
  };
  ScriptRunner(Script script, Session& session, ViewState& view) : script_(std::move(script)), session_(session), view_(view) {}

  // Runs commands until one must wait. `screenshot(base)` writes the screenshot files.
  // Throws ScriptError "FILE:LINE: message" for a command that fails (a bad option value,
  // a view that needs a missing reference, an output refused, a render error).
  Step step(const std::function<void(const std::string& base)>& screenshot);
  // The command being run, for error messages ("FILE:LINE").
  std::string where() const;

 private:
  void run(const ScriptCommand& c, const std::function<void(const std::string&)>& screenshot);
  Script script_;
  Session& session_;
  ViewState& view_;
  size_t next_ = 0;
  bool waiting_ = false;
  bool waiting_reference_ = false;  // for the background reference, not for frames
};

}  // namespace rl::viewer
