// `restir view`: the interactive viewer's entry point (defined in viewer/gui/, built only with
// RESTIR_VIEWER; app/main.cpp reports a build without it).
#pragma once
#include "viewer/session.h"

namespace rl::viewer {

// Opens the window and runs until it is closed, the script ends (--script) or the bench is done
// (--bench). Throws SceneError / OptionError / ScriptError for bad input (one line, naming the
// file), ViewerError when there is no window.
int run_view(const ViewArgs& args);

}  // namespace rl::viewer
