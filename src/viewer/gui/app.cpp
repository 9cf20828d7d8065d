// The viewer's window loop: GLFW window and OpenGL 3 context, Dear ImGui, the frame texture,
// mouse / keyboard camera control, script mode, window captures and the bench.
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <GLFW/glfw3.h>
#include <fmt/format.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <utility>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/output_guard.h"
#include "image/flip.h"
#include "image/image_io.h"
#include "image/metrics.h"
#include "image/tonemap.h"
#include "viewer/gui/gui.h"
#include "viewer/script_runner.h"
#include "viewer/view.h"

namespace rl::viewer {

namespace {

constexpr float kPanelWidth = 420;

// Window state the GLFW callbacks (plain functions) write.
std::string glfw_error = "unknown reason";
bool glfw_open = false;
bool input_events = false;  // set by the window's input callbacks, cleared by ui_iteration
// F12 and Ctrl+Q as they are pressed: ImGui 1.86 polls key state once a frame and misses a press
// and release that arrive together (as from xdotool).
bool key_screenshot = false, key_quit = false;

double now_s() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

bool same(const OutputOptions& a, const OutputOptions& b) {
  return a.tonemap == b.tonemap && a.exposure == b.exposure && a.white_point == b.white_point && a.srgb == b.srgb;
}

// relMSE on every frame (cheap); FLIP (a few filters over the image) at most once a second.
void update_metrics(Gui& g, bool force_flip) {
  const Image* ref = g.session.reference();
  if (!ref || ref->width != g.hdr.width || ref->height != g.hdr.height) {
    g.rel_mse = g.flip = -1;
    return;
  }
  try {
    g.rel_mse = rel_mse(g.hdr, *ref);
    if (force_flip || now_s() - g.last_flip_time > 1.0) {
      const OutputOptions& o = g.session.options().output;
      g.flip = mean_flip(tonemap(g.hdr, o), tonemap(*ref, o));
      g.last_flip_time = now_s();
    }
  } catch (const std::exception&) {
    g.rel_mse = g.flip = -1;  // a non-finite pixel: the worker reports it as an error
  }
}

// Takes a new frame (or re-reads the shown one when the view changed) and redraws the texture;
// false when nothing changed.
bool refresh_display(Gui& g) {
  ViewState& last_view = g.shown_view;
  OutputOptions& last_output = g.shown_output;
  float& last_scale = g.shown_scale;
  const OutputOptions& out = g.session.options().output;
  const bool view_changed = last_view.mode != g.view.mode || last_view.split != g.view.split ||
                            last_view.accumulate != g.view.accumulate || !same(last_output, out) || last_scale != g.session.scale();
  const double t0 = now_s();
  const bool fresh = g.session.take_frame(g.view.accumulate, view_changed, g.hdr, g.readout);
  if (!fresh || g.hdr.empty()) return false;
  const double t1 = now_s();
  if (g.readout.serial != g.last_serial || g.readout.reference_serial != g.shown_reference_serial) {
    g.last_serial = g.readout.serial;
    g.shown_reference_serial = g.readout.reference_serial;
    update_metrics(g, false);
  } else if (last_view.accumulate != g.view.accumulate) {
    update_metrics(g, true);
  }
  last_view = g.view;
  last_output = out;
  last_scale = g.session.scale();
  // The radiance view is tone mapped by the GPU (display_gl.h); the error map and the split view,
  // and every view without the shader, on the CPU.
  const bool gpu = g.display.gpu() && (g.view.mode == ViewMode::radiance || !g.session.reference());
  if (!gpu) g.ldr = compose_view(g.view.mode, g.hdr, g.session.reference(), out, g.view.split);
  const double t2 = now_s();
  if (gpu) g.display.show_hdr(g.hdr, out);
  else g.display.show_ldr(g.ldr);
  g.cost.take_ms += (t1 - t0) * 1000;
  g.cost.compose_ms += (t2 - t1) * 1000;
  g.cost.upload_ms += (now_s() - t2) * 1000;
  return true;
}

// Mouse: left drag turns (orbit / look), right drag pans, wheel dollies. Keys: WASD, Q/E down/up,
// Shift faster, R reset, Space pause, F12 screenshot, Ctrl+Q quit.
void camera_input(Gui& g, double dt) {
  ImGuiIO& io = ImGui::GetIO();
  CameraController& cam = g.session.camera();
  bool moved = false;
  if (!io.WantCaptureMouse) {
    const ImVec2 d = io.MouseDelta;
    if (ImGui::IsMouseDragging(ImGuiMouseButton_Left, 0) && (d.x != 0 || d.y != 0)) cam.rotate(d.x * 0.3f, d.y * 0.3f), moved = true;
    if (ImGui::IsMouseDragging(ImGuiMouseButton_Right, 0) && (d.x != 0 || d.y != 0))
      cam.move(Vec3(-d.x * 0.001f, d.y * 0.001f, 0)), moved = true;
    if (io.MouseWheel != 0) cam.move(Vec3(0, 0, io.MouseWheel * 0.05f)), moved = true;
  }
  if (!io.WantCaptureKeyboard) {
    auto down = [&](int key) { return glfwGetKey(g.window, key) == GLFW_PRESS; };
    const float speed = float(dt) * (down(GLFW_KEY_LEFT_SHIFT) ? 0.5f : 0.1f);
    Vec3 m(0);
    if (down(GLFW_KEY_W)) m.z += speed;
    if (down(GLFW_KEY_S)) m.z -= speed;
    if (down(GLFW_KEY_D)) m.x += speed;
    if (down(GLFW_KEY_A)) m.x -= speed;
    if (down(GLFW_KEY_E)) m.y += speed;
    if (down(GLFW_KEY_Q)) m.y -= speed;
    if ((m.x != 0 || m.y != 0 || m.z != 0) && !io.KeyCtrl) cam.move(m), moved = true;
    if (ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Space), false) && !io.WantTextInput) {
      g.paused = !g.paused;
      g.session.set_paused(g.paused);
    }
    if (glfwGetKey(g.window, GLFW_KEY_R) == GLFW_PRESS && !io.WantTextInput) cam.reset(), moved = true;
    if (std::exchange(key_screenshot, false)) {
      try {
        g.save_screenshot(g.screenshot_path);
        g.say(std::string("saved ") + g.screenshot_path + ".exr/.png/.json");
      } catch (const std::exception& e) {
        g.say(e.what(), true);
      }
    }
    if (std::exchange(key_quit, false)) glfwSetWindowShouldClose(g.window, GLFW_TRUE);
  }
  if (moved) g.session.camera_moved();
}

// The frame image, fitted into the window left of the panel, aspect kept.
void draw_image(Gui& g) {
  if (g.display.width() == 0) return;
  const ImVec2 size = ImGui::GetIO().DisplaySize;
  const float aw = std::max(1.0f, size.x - kPanelWidth), ah = size.y;
  const float s = std::min(aw / float(g.display.width()), ah / float(g.display.height()));
  const float w = float(g.display.width()) * s, h = float(g.display.height()) * s;
  const ImVec2 p0((aw - w) * 0.5f, (ah - h) * 0.5f);
  ImGui::GetBackgroundDrawList()->AddImage(ImTextureID(intptr_t(g.display.texture())), p0, ImVec2(p0.x + w, p0.y + h));
  if (g.view.mode == ViewMode::split && g.session.reference()) {
    const float x = p0.x + w * g.view.split;
    ImGui::GetBackgroundDrawList()->AddLine(ImVec2(x, p0.y), ImVec2(x, p0.y + h), IM_COL32(255, 255, 255, 200), 1.5f);
  }
}

void capture_window(Gui& g, const std::string& path) {
  int w = 0, h = 0;
  glfwGetFramebufferSize(g.window, &w, &h);
  std::vector<uint8_t> px(size_t(w) * size_t(h) * 3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, px.data());
  Image img(w, h);
  for (int y = 0; y < h; ++y)  // GL rows start at the bottom
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) img.at(x, h - 1 - y)[c] = float(px[(size_t(y) * size_t(w) + size_t(x)) * 3 + size_t(c)]) / 255.0f;
  write_png(path, img);
}

void draw_frame(Gui& g, double dt, bool interactive) {
  const double t0 = now_s();
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  if (interactive) camera_input(g, dt);
  draw_image(g);
  draw_panels(g, kPanelWidth);
  ImGui::Render();
  int fw = 0, fh = 0;
  glfwGetFramebufferSize(g.window, &fw, &fh);
  glViewport(0, 0, fw, fh);
  glClearColor(0.08f, 0.08f, 0.08f, 1);
  glClear(GL_COLOR_BUFFER_BIT);
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  if (!g.capture.empty()) {
    capture_window(g, g.capture);
    g.capture.clear();
  }
  glfwSwapBuffers(g.window);
  g.cost.draw_ms += (now_s() - t0) * 1000;
  ++g.cost.draws;
}


// The window, its GL context and ImGui, released in reverse order.
struct Window {
  GLFWwindow* w = nullptr;
  Window(int width, int height, bool visible) {
    // Until the window is open, GLFW's reason goes into the one error line; after, it is a warning.
    glfwSetErrorCallback([](int, const char* msg) {
      if (glfw_open) std::fprintf(stderr, "warning: GLFW: %s\n", msg);
      else glfw_error = msg;
    });
    if (!glfwInit())
      throw ViewerError("view: cannot open a window: " + glfw_error + " (set DISPLAY, or run under xvfb-run)");
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
    w = glfwCreateWindow(width, height, "restir view", nullptr, nullptr);
    if (!w) {
      glfwTerminate();
      throw ViewerError("view: cannot create an OpenGL 3.3 window: " + glfw_error);
    }
    glfw_open = true;
    glfwMakeContextCurrent(w);
    glfwSwapInterval(1);
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini in the working folder
    ImGui::StyleColorsDark();
    // Installed first: ImGui's backend chains to them. They only note that input arrived.
    glfwSetCursorPosCallback(w, [](GLFWwindow*, double, double) { input_events = true; });
    glfwSetMouseButtonCallback(w, [](GLFWwindow*, int, int, int) { input_events = true; });
    glfwSetScrollCallback(w, [](GLFWwindow*, double, double) { input_events = true; });
    glfwSetKeyCallback(w, [](GLFWwindow*, int key, int, int action, int mods) {
      input_events = true;
      if (action != GLFW_PRESS || ImGui::GetIO().WantTextInput) return;
      if (key == GLFW_KEY_F12) key_screenshot = true;
      if (key == GLFW_KEY_Q && (mods & GLFW_MOD_CONTROL)) key_quit = true;
    });
    glfwSetCharCallback(w, [](GLFWwindow*, unsigned) { input_events = true; });
    glfwSetWindowSizeCallback(w, [](GLFWwindow*, int, int) { input_events = true; });
    glfwSetWindowRefreshCallback(w, [](GLFWwindow*) { input_events = true; });
    ImGui_ImplGlfw_InitForOpenGL(w, true);
    ImGui_ImplOpenGL3_Init("#version 330");
  }
  ~Window() {
    glfw_open = false;
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    glfwDestroyWindow(w);
    glfwTerminate();
  }
};

}  // namespace

void Gui::save_screenshot(const std::string& base) {
  session.take_frame(view.accumulate, true, hdr, readout);
  if (hdr.empty()) throw ViewerError("screenshot: no frame rendered yet");
  const OutputOptions& out = session.options().output;
  ldr = compose_view(view.mode, hdr, session.reference(), out, view.split);
  // The window shows this very frame; on the GPU path, check the shader against tonemap_pixel.
  const bool gpu = display.gpu() && (view.mode == ViewMode::radiance || !session.reference());
  int display_diff = 0;
  if (gpu) {
    display.show_hdr(hdr, out);
    display_diff = display.max_difference(ldr);
  } else {
    display.show_ldr(ldr);
  }
  update_metrics(*this, true);
  const std::string view_json = fmt::format(
      "{{\"view\": \"{}\", \"split\": {}, \"accumulate\": {}, \"scale\": {}, \"rel_mse\": {}, \"flip\": {}, "
      "\"display\": \"{}\", \"display_max_difference\": {}, \"reference\": \"{}\", \"reference_spp\": {}, "
      "\"reference_own_rel_mse\": {}, \"ms_per_frame\": {:.6g}}}",
      view_name(view.mode), view.split, view.accumulate ? "true" : "false", session.scale(),
      rel_mse >= 0 ? fmt::format("{:.9g}", rel_mse) : "null", flip >= 0 ? fmt::format("{:.9g}", flip) : "null",
      gpu ? "gpu" : "cpu", display_diff,
      !session.reference() ? "none" : session.has_reference_file() ? "file" : "background",
      session.has_reference_file() || !session.reference() ? 0 : session.reference_spp(),
      session.reference() && session.reference_own_rel_mse() >= 0 ? fmt::format("{:.9g}", session.reference_own_rel_mse())
                                                                   : "null",
      history.mean_ms());
  std::string stem = base;
  for (const char* ext : {".exr", ".png"})
    if (stem.size() > 4 && stem.compare(stem.size() - 4, 4, ext) == 0) stem.resize(stem.size() - 4);
  check_outputs({{stem + ".window.png", "window capture", {".png"}}}, session.inputs());
  session.screenshot(base, hdr, ldr, readout, view_json);
  capture = stem + ".window.png";
}

namespace {

// Window size: the image at its film size (at most 1280x800), the panel beside it.
void window_size(const ViewArgs& a, const Options& o, int& w, int& h) {
  if (a.width > 0 && a.height > 0) {
    w = a.width;
    h = a.height;
    return;
  }
  const double s = std::min({1.0, 1280.0 / o.film.width, 800.0 / o.film.height});
  w = int(o.film.width * s) + int(kPanelWidth);
  h = std::max(720, int(o.film.height * s));
}

// True while the user holds a control that acts on every drawn frame (a mouse button, a camera key).
bool controls_held(GLFWwindow* w) {
  for (int b : {GLFW_MOUSE_BUTTON_LEFT, GLFW_MOUSE_BUTTON_RIGHT, GLFW_MOUSE_BUTTON_MIDDLE})
    if (glfwGetMouseButton(w, b) == GLFW_PRESS) return true;
  for (int k : {GLFW_KEY_W, GLFW_KEY_A, GLFW_KEY_S, GLFW_KEY_D, GLFW_KEY_Q, GLFW_KEY_E})
    if (glfwGetKey(w, k) == GLFW_PRESS) return true;
  return false;
}

// The worker's frame times into the ms/frame readout: interactive and script mode alike (script
// mode once showed 0.0 ms/frame after 8 frames: only the interactive loop took them).
void take_frame_times(Gui& g) {
  for (double ms : g.session.take_frame_times()) g.history.add(ms);
}

// One turn of the interactive loop. It sleeps until input, a new frame (the worker posts an empty
// event) or the pacer's next redraw, and draws only when the pacer says so (DrawPacer: at once on
// input, else within the redraw budget): on a CPU-bound renderer every redraw is taken from the
// render threads.
void ui_iteration(Gui& g, double dt, bool interactive) {
  const double wait = g.pacer.wait_s(now_s(), g.session.frame_waiting());
  if (wait > 1e-4) glfwWaitEventsTimeout(wait);
  else glfwPollEvents();
  take_frame_times(g);
  const bool input = std::exchange(input_events, false) || controls_held(g.window);
  const double t0 = now_s();
  if (!g.pacer.due(t0, input, g.session.frame_waiting())) return;
  refresh_display(g);
  draw_frame(g, dt, interactive);
  const double t1 = now_s();
  g.pacer.drawn(t1, t1 - t0, input);
}

int run_script(Gui& g, Script script) {
  ScriptRunner runner(std::move(script), g.session, g.view);
  g.session.start([] { glfwPostEmptyEvent(); });
  for (;;) {
    ScriptRunner::Step st;
    try {
      st = runner.step([&](const std::string& base) { g.save_screenshot(base); });
    } catch (const std::exception& e) {
      g.session.stop();
      throw;
    }
    if (st == ScriptRunner::Step::done) break;
    if (st == ScriptRunner::Step::waiting) glfwWaitEventsTimeout(0.05);
    else glfwPollEvents();
    take_frame_times(g);
    refresh_display(g);
    draw_frame(g, 0, false);
    if (glfwWindowShouldClose(g.window)) break;
  }
  g.session.stop();
  return 0;
}

int run_interactive(Gui& g) {
  g.session.start([] { glfwPostEmptyEvent(); });
  double last = now_s();
  while (!glfwWindowShouldClose(g.window)) {
    const double t = now_s();
    ui_iteration(g, t - last, true);
    last = t;
  }
  g.session.stop();
  return 0;
}

// Wall and CPU time (this process: render threads, UI thread, the OpenGL driver's threads) per frame.
struct BenchTime {
  double wall_ms = 0, cpu_ms = 0;
};

double cpu_s() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + double(u.ru_utime.tv_usec + u.ru_stime.tv_usec) * 1e-6;
}

// N frames as `restir render` renders them: FrameRenderer and the running mean, after a warm-up
// frame (first-touch allocations).
BenchTime bench_bare(const Scene& scene, const Options& o, const CameraKey& key, int n) {
  FrameRenderer r(scene, o);
  Image img, mean;
  r.render_frame(key, o.render.frames, img, nullptr);
  mean = img;
  const double t0 = now_s(), c0 = cpu_s();
  for (int f = 0; f < n; ++f) {
    StageTimes st;
    r.render_frame(key, o.render.frames, img, &st);
    accumulate_mean(mean, img, f + 2);
  }
  return {(now_s() - t0) * 1000 / n, (cpu_s() - c0) * 1000 / n};
}

// N frames through the interactive loop, timed from the first frame rendered to the n-th after it
// (the session's first frame builds the BVH, as the bare loop's untimed warm-up does). The window
// shows what the pacer lets it; the time is the renderer's, with the window's redraws beside it.
BenchTime bench_viewer(Gui& g, int n, int round) {
  const long long before = g.session.frames_completed();
  g.session.render_frames(n + 1);
  double t0 = -1, c0 = 0;
  UiCost cost0;
  while (g.session.frames_completed() < before + n + 1) {
    ui_iteration(g, 0, false);
    if (t0 < 0 && g.session.frames_completed() > before) t0 = now_s(), c0 = cpu_s(), cost0 = g.cost;
    if (!g.session.error().empty()) throw ViewerError("bench: " + g.session.error());
  }
  const BenchTime t{(now_s() - t0) * 1000 / n, (cpu_s() - c0) * 1000 / n};
  const UiCost& c = g.cost;
  std::fprintf(stderr, "bench round %d: viewer %.2f ms/frame (CPU %.2f); UI thread per frame: take %.2f, display transform "
               "%.2f, upload %.2f, draw %.2f ms, %.2f redraws (redraw budget %.0f%%, redraw %.1f ms)\n", round, t.wall_ms, t.cpu_ms,
               (c.take_ms - cost0.take_ms) / n, (c.compose_ms - cost0.compose_ms) / n, (c.upload_ms - cost0.upload_ms) / n,
               (c.draw_ms - cost0.draw_ms) / n, double(c.draws - cost0.draws) / n, g.pacer.budget() * 100, g.pacer.cost_s() * 1000);
  return t;
}

// --bench N: the same N frames rendered bare and through the viewer loop (worker thread, display
// transform, texture upload, ImGui drawing), alternating kBenchRounds times so that a change in
// the machine's load (it is shared) falls on both alike. Prints wall and CPU time per frame and
// their ratios: the CPU ratio is the work the viewer adds, whatever else the machine runs.
int run_bench(Gui& g, int n) {
  const Options o = g.session.effective_options();
  const CameraKey key = g.session.camera().key();
  g.session.render_frames(0);
  g.session.start([] { glfwPostEmptyEvent(); });
  constexpr int kBenchRounds = 5;
  BenchTime bare, viewer;
  std::vector<double> wall_ratio, cpu_ratio;  // per round: the machine's load drifts between rounds
  for (int round = 0; round < kBenchRounds; ++round) {
    const BenchTime b = bench_bare(g.session.scene(), o, key, n);
    std::fprintf(stderr, "bench round %d: bare   %.2f ms/frame (CPU %.2f)\n", round, b.wall_ms, b.cpu_ms);
    const BenchTime v = bench_viewer(g, n, round);
    bare.wall_ms += b.wall_ms / kBenchRounds;
    bare.cpu_ms += b.cpu_ms / kBenchRounds;
    viewer.wall_ms += v.wall_ms / kBenchRounds;
    viewer.cpu_ms += v.cpu_ms / kBenchRounds;
    wall_ratio.push_back(v.wall_ms / b.wall_ms);
    cpu_ratio.push_back(v.cpu_ms / b.cpu_ms);
  }
  g.session.stop();
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  std::printf("bench %s %s %dx%d spp %d: bare %.2f ms/frame (%.2f fps), viewer %.2f ms/frame (%.2f fps): "
              "viewer/bare wall %.3f (%+.1f%%), CPU %.3f (%+.1f%%); median of %d rounds: wall %+.1f%%, CPU %+.1f%% "
              "(redraw budget %.0f%%)\n",
              o.integrator.c_str(), g.session.args().scene.c_str(), o.film.width, o.film.height, o.render.spp, bare.wall_ms,
              1000 / bare.wall_ms, viewer.wall_ms, 1000 / viewer.wall_ms, viewer.wall_ms / bare.wall_ms,
              (viewer.wall_ms / bare.wall_ms - 1) * 100, viewer.cpu_ms / bare.cpu_ms, (viewer.cpu_ms / bare.cpu_ms - 1) * 100,
              kBenchRounds, (median(wall_ratio) - 1) * 100, (median(cpu_ratio) - 1) * 100, g.pacer.budget() * 100);
  return 0;
}

}  // namespace

int run_view(const ViewArgs& a) {
  std::optional<Script> script;
  if (!a.script.empty()) script = load_script(a.script);  // bad scripts fail before the window opens
  Session session(a);
  int w = 0, h = 0;
  window_size(a, session.options(), w, h);
  Window window(w, h, true);
  Gui g(session);
  g.window = window.w;
  g.pacer.set_budget(a.redraw_budget);
  g.display.init();
  if (a.bench > 0) return run_bench(g, a.bench);
  if (script) {
    session.render_frames(0);  // frames only when the script asks
    return run_script(g, std::move(*script));
  }
  return run_interactive(g);
}

}  // namespace rl::viewer
