// The viewer's window loop: GLFW window and OpenGL 3 context, Dear ImGui, the frame texture,
// mouse / keyboard camera control, script mode, window captures and the bench.
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <GLFW/glfw3.h>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
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

// Takes a new frame (or re-reads the shown one when the view changed) and redraws the texture.
void refresh_display(Gui& g) {
  ViewState& last_view = g.shown_view;
  OutputOptions& last_output = g.shown_output;
  float& last_scale = g.shown_scale;
  const OutputOptions& out = g.session.options().output;
  const bool view_changed = last_view.mode != g.view.mode || last_view.split != g.view.split ||
                            last_view.accumulate != g.view.accumulate || !same(last_output, out) || last_scale != g.session.scale();
  const double t0 = now_s();
  const bool fresh = g.session.take_frame(g.view.accumulate, view_changed, g.hdr, g.readout);
  if (!fresh || g.hdr.empty()) return;
  const double t1 = now_s();
  if (g.readout.serial != g.last_serial) {
    g.history.add(g.readout.ms);
    g.last_serial = g.readout.serial;
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
}

// Mouse: left drag turns (orbit / look), right drag pans, wheel dollies. Keys: WASD, Q/E down/up,
// Shift faster, R reset, Space pause.
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
    if (m.x != 0 || m.y != 0 || m.z != 0) cam.move(m), moved = true;
    if (ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Space), false) && !io.WantTextInput) {
      g.paused = !g.paused;
      g.session.set_paused(g.paused);
    }
    if (glfwGetKey(g.window, GLFW_KEY_R) == GLFW_PRESS && !io.WantTextInput) cam.reset(), moved = true;
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

std::string glfw_error = "unknown reason";
bool glfw_open = false;

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
      throw std::runtime_error("view: cannot open a window: " + glfw_error + " (set DISPLAY, or run under xvfb-run)");
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
    w = glfwCreateWindow(width, height, "restir view", nullptr, nullptr);
    if (!w) {
      glfwTerminate();
      throw std::runtime_error("view: cannot create an OpenGL 3.3 window: " + glfw_error);
    }
    glfw_open = true;
    glfwMakeContextCurrent(w);
    glfwSwapInterval(1);
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini in the working folder
    ImGui::StyleColorsDark();
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
  if (hdr.empty()) throw std::runtime_error("screenshot: no frame rendered yet");
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
      "\"display\": \"{}\", \"display_max_difference\": {}}}",
      view_name(view.mode), view.split, view.accumulate ? "true" : "false", session.scale(),
      rel_mse >= 0 ? fmt::format("{:.9g}", rel_mse) : "null", flip >= 0 ? fmt::format("{:.9g}", flip) : "null",
      gpu ? "gpu" : "cpu", display_diff);
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

// One turn of the interactive loop. It sleeps until input or a new frame (the worker posts an
// empty event), at most 0.25 s: an idle window costs nothing, and the loop draws once per
// rendered frame (plus input) rather than spinning beside the render threads.
void ui_iteration(Gui& g, double dt, bool interactive) {
  glfwWaitEventsTimeout(0.25);
  refresh_display(g);
  draw_frame(g, dt, interactive);
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

// --bench N: the same N frames rendered bare (FrameRenderer and the running mean, as `restir
// render` does) and through the viewer loop (worker thread, display transform, texture upload,
// ImGui drawing), alternating twice; prints both and their ratio.
int run_bench(Gui& g, int n) {
  const Options o = g.session.effective_options();
  const CameraKey key = g.session.camera().key();
  g.session.render_frames(0);
  g.session.start([] { glfwPostEmptyEvent(); });
  double bare_total = 0, viewer_total = 0;
  for (int round = 0; round < 2; ++round) {
    {
      FrameRenderer r(g.session.scene(), o);
      Image img, mean;
      r.render_frame(key, o.render.frames, img, nullptr);  // warm-up: first-touch allocations
      mean = img;
      const double t0 = now_s();
      for (int f = 0; f < n; ++f) {
        StageTimes st;
        r.render_frame(key, o.render.frames, img, &st);
        accumulate_mean(mean, img, f + 2);
      }
      const double ms = (now_s() - t0) * 1000 / n;
      bare_total += ms;
      std::fprintf(stderr, "bench round %d: bare   %.2f ms/frame\n", round, ms);
    }
    // Timed from the first frame shown to the n-th after it: the worker's first frame of the
    // session builds the BVH, which the bare loop's warm-up frame excludes too.
    const long long before = g.last_serial;
    g.session.render_frames(n + 1);
    double t0 = -1;
    long long first = -1;
    const UiCost cost0 = g.cost;
    while (!(first >= 0 && g.last_serial >= first + n)) {
      ui_iteration(g, 0, false);
      if (first < 0 && g.last_serial > before) first = g.last_serial, t0 = now_s();
      if (!g.session.error().empty()) throw std::runtime_error("bench: " + g.session.error());
    }
    const double ms = (now_s() - t0) * 1000 / n;
    viewer_total += ms;
    const UiCost& c = g.cost;
    std::fprintf(stderr, "bench round %d: viewer %.2f ms/frame; UI thread per frame: take %.2f, display transform %.2f, "
                 "upload %.2f, draw %.2f ms (%.2f draws per frame)\n", round, ms, (c.take_ms - cost0.take_ms) / n,
                 (c.compose_ms - cost0.compose_ms) / n, (c.upload_ms - cost0.upload_ms) / n, (c.draw_ms - cost0.draw_ms) / n,
                 double(c.draws - cost0.draws) / n);
  }
  g.session.stop();
  const double bare = bare_total / 2, viewer = viewer_total / 2;
  std::printf("bench %s %s %dx%d spp %d: bare %.2f ms/frame (%.2f fps), viewer %.2f ms/frame (%.2f fps), "
              "viewer/bare %.3f (%+.1f%%)\n",
              o.integrator.c_str(), g.session.args().scene.c_str(), o.film.width, o.film.height, o.render.spp, bare,
              1000 / bare, viewer, 1000 / viewer, viewer / bare, (viewer / bare - 1) * 100);
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
  g.display.init();
  if (a.bench > 0) return run_bench(g, a.bench);
  if (script) {
    session.render_frames(0);  // frames only when the script asks
    return run_script(g, std::move(*script));
  }
  return run_interactive(g);
}

}  // namespace rl::viewer
