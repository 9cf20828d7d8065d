// The viewer's window (GLFW 3 + Dear ImGui + OpenGL 3): what the window loop (app.cpp) and the
// panels (panels.cpp) share. Only this folder includes GL or ImGui headers.
#pragma once
#include <string>

#include "viewer/display.h"
#include "viewer/gui/display_gl.h"
#include "viewer/session.h"

struct GLFWwindow;

namespace rl::viewer {

// Where the UI thread's time goes (ms, summed), printed by the bench.
struct UiCost {
  double take_ms = 0, compose_ms = 0, upload_ms = 0, draw_ms = 0;
  long long draws = 0;
};

struct Gui {
  explicit Gui(Session& s) : session(s) {}
  Session& session;
  GLFWwindow* window = nullptr;
  GlDisplay display;  // the texture the window shows

  ViewState view;
  Image hdr, ldr;          // the shown frame (mean or raw) and its display image (CPU views)
  FrameReadout readout;
  FrameHistory history{300};
  long long last_serial = 0;
  double rel_mse = -1, flip = -1;  // against the reference; < 0: not computed
  double last_flip_time = -1e9;
  bool paused = false;
  UiCost cost;
  DrawPacer pacer;  // when to redraw (display.h)
  long long shown_reference_serial = 0;  // the background reference the metrics were computed against
  ViewState shown_view;      // what the texture shows, to tell when to redraw it
  OutputOptions shown_output;
  float shown_scale = 0;

  std::string status;      // the last message: a saved file or a refused value
  bool status_error = false;
  std::string capture;     // a window PNG to write after the next draw (empty: none)
  char screenshot_path[512] = "out/view";
  char config_path[512] = "out/view-config.json";
  char camera_path[512] = "out/view-camera.json";

  void say(const std::string& text, bool error = false) {
    status = text;
    status_error = error;
  }
  // Writes the screenshot files of the shown frame and queues the window capture BASE.window.png.
  void save_screenshot(const std::string& base);
};

// The side panel: readouts, view, camera, files and one widget per option (option_model.h).
void draw_panels(Gui& g, float width);

}  // namespace rl::viewer
