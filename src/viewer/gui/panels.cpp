// The side panel of the viewer. The option widgets are generated from option_widgets(), i.e. from
// visit_options: a new option appears here without any change to this file.
#include <imgui.h>

#include <fmt/format.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "viewer/gui/gui.h"
#include "viewer/script.h"

namespace rl::viewer {

namespace {

void help_tooltip(const std::string& text) {
  if (ImGui::IsItemHovered()) {
    ImGui::BeginTooltip();
    ImGui::PushTextWrapPos(ImGui::GetFontSize() * 30);
    ImGui::TextUnformatted(text.c_str());
    ImGui::PopTextWrapPos();
    ImGui::EndTooltip();
  }
}

// One option's widget; returns the new value text when the user changed it.
bool option_widget(const OptionWidget& w, const std::string& value, std::string& out) {
  const char* id = w.key.c_str();
  switch (w.kind) {
    case WidgetKind::checkbox: {
      bool b = value == "true";
      if (ImGui::Checkbox(id, &b)) return out = b ? "true" : "false", true;
      return false;
    }
    case WidgetKind::combo: {
      int cur = 0;
      for (size_t i = 0; i < w.choices.size(); ++i)
        if (w.choices[i] == value) cur = int(i);
      bool changed = false;
      if (ImGui::BeginCombo(id, value.c_str())) {
        for (size_t i = 0; i < w.choices.size(); ++i)
          if (ImGui::Selectable(w.choices[i].c_str(), int(i) == cur)) out = w.choices[i], changed = true;
        ImGui::EndCombo();
      }
      return changed;
    }
    case WidgetKind::slider:
    case WidgetKind::drag: {
      const bool slider = w.kind == WidgetKind::slider;
      if (w.is_float) {
        float f = 0, lo = float(w.lo), hi = float(w.hi);
        parse_float(value, f);
        const bool c = slider ? ImGui::SliderFloat(id, &f, lo, hi, "%.4g")
                              : ImGui::DragFloat(id, &f, std::max(1e-3f, std::fabs(f) * 0.01f), lo, hi, "%.4g",
                                                 ImGuiSliderFlags_AlwaysClamp);
        if (c) return out = fmt::format("{}", f), true;
      } else {
        int i = 0;
        const int lo = std::isfinite(w.lo) ? int(w.lo) : -(1 << 30), hi = std::isfinite(w.hi) ? int(std::min(w.hi, 2e9)) : 1 << 30;
        parse_int(value, i);
        const bool c = slider ? ImGui::SliderInt(id, &i, lo, hi) : ImGui::DragInt(id, &i, 1.0f, lo, hi, "%d", ImGuiSliderFlags_AlwaysClamp);
        if (c) return out = std::to_string(i), true;
      }
      return false;
    }
    case WidgetKind::seed: {
      unsigned long long v = std::strtoull(value.c_str(), nullptr, 10);
      if (ImGui::InputScalar(id, ImGuiDataType_U64, &v, nullptr, nullptr, "%llu", ImGuiInputTextFlags_EnterReturnsTrue))
        return out = std::to_string(v), true;
      return false;
    }
    case WidgetKind::text: {
      char buf[1024];
      std::snprintf(buf, sizeof buf, "%s", value.c_str());
      if (ImGui::InputText(id, buf, sizeof buf, ImGuiInputTextFlags_EnterReturnsTrue)) return out = buf, true;
      return false;
    }
  }
  return false;
}

// The background reference's own relMSE beside the metrics: the relMSE against a noisy reference
// is the frames' error plus the reference's, so a value near the reference's own says nothing about
// the frames (a 32-spp reference of a scene with fireflies has a relMSE of hundreds by itself).
void reference_noise(const Gui& g) {
  const double own = g.session.reference_own_rel_mse();
  if (own < 0) return;
  ImGui::Text("  the reference's own relMSE ~%s (%d spp)", fmt::format("{:.5f}", own).c_str(), g.session.reference_spp());
  if (g.rel_mse >= 0 && g.rel_mse < 2 * own) {
    ImGui::SameLine();
    ImGui::TextUnformatted(": relMSE not resolved");
    help_tooltip("the relMSE is less than twice the reference's own: most of it may be the reference's noise; let "
                 "the reference run longer (reference target spp)");
  }
}

void readouts(Gui& g) {
  const FrameReadout& r = g.readout;
  const Options& o = g.session.options();
  ImGui::Text("%s  %dx%d (scale %g)", o.integrator.c_str(), r.width, r.height, g.session.scale());
  ImGui::Text("%.1f ms/frame  %.2f fps  (last %.1f ms)", g.history.mean_ms(), g.history.fps(), r.ms);
  ImGui::Text("frames accumulated %d  (%d spp)  frame %d", r.accumulated, r.accumulated * o.render.spp, r.frame);
  if (g.session.has_reference_file() && !g.session.reference()) {
    ImGui::TextUnformatted("reference: not the film's size (no metrics)");
  } else if (g.session.has_reference() && !g.session.reference()) {
    ImGui::TextUnformatted("reference: rendering the first pass");
  } else if (g.session.reference()) {
    ImGui::Text("relMSE %s   FLIP %s", g.rel_mse >= 0 ? fmt::format("{:.5f}", g.rel_mse).c_str() : "-",
                g.flip >= 0 ? fmt::format("{:.4f}", g.flip).c_str() : "-");
    reference_noise(g);
  }
  const std::vector<float> v = g.history.values();
  if (!v.empty()) {
    const float top = *std::max_element(v.begin(), v.end()) * 1.1f;
    const std::string label = fmt::format("ms per frame, last {} (0 - {:.0f})", v.size(), top);
    ImGui::PlotLines("##ms", v.data(), int(v.size()), 0, label.c_str(), 0.0f, top,
                     ImVec2(ImGui::GetContentRegionAvail().x, 60));
  }
  if (ImGui::TreeNodeEx("stages", ImGuiTreeNodeFlags_DefaultOpen)) {
    // Each stage's time and, where it traced rays, its rays per pixel by kind (core/ray_counter.h).
    const double px = std::max(1.0, double(r.width) * double(r.height));
    for (const auto& [name, ms] : r.stages.ms) {
      const RayCounts c = r.stages.rays_of(name);
      if (c.total() > 0)
        ImGui::Text("%-20s %8.2f ms  %5.2f + %5.2f rays/px", name.c_str(), ms, double(c.closest) / px, double(c.any) / px);
      else
        ImGui::Text("%-20s %8.2f ms", name.c_str(), ms);
    }
    const RayCounts all = r.stages.total_rays();
    if (all.total() > 0)
      ImGui::Text("rays per pixel: %.2f closest-hit + %.2f any-hit", double(all.closest) / px, double(all.any) / px);
    ImGui::TreePop();
  }
}

// The background reference (session.h): a pt image of the view rendered beside the frames.
void reference_controls(Gui& g) {
  if (g.session.has_reference_file()) {
    ImGui::Text("reference: %s", g.session.args().reference.c_str());
    return;
  }
  ReferenceSettings r = g.session.reference_settings();
  bool changed = ImGui::Checkbox("background reference", &r.on);
  help_tooltip("render a path-traced reference of this view beside the frames (pt, its own seed; restarts when the "
               "camera, film, path length or scene frame changes, not when ReSTIR's options do)");
  ImGui::SameLine();
  ImGui::Text("%d spp", g.session.reference_spp());
  float share = r.share * 100;
  if (ImGui::SliderFloat("reference share %", &share, 5, 95, "%.0f")) r.share = share / 100, changed = true;
  help_tooltip("its share of the render time while frames render (all of it while paused)");
  if (ImGui::InputInt("reference target spp", &r.target_spp, 256, 4096, ImGuiInputTextFlags_EnterReturnsTrue)) changed = true;
  if (!changed) return;
  try {
    g.session.set_reference(r);
  } catch (const std::exception& e) {
    g.say(e.what(), true);
  }
}

void view_controls(Gui& g) {
  const bool ref = g.session.reference() != nullptr;
  int mode = int(g.view.mode);
  ImGui::RadioButton("radiance", &mode, int(ViewMode::radiance));
  ImGui::SameLine();
  if (!ref) ImGui::BeginDisabled();
  ImGui::RadioButton("error map", &mode, int(ViewMode::error));
  ImGui::SameLine();
  ImGui::RadioButton("A/B split", &mode, int(ViewMode::split));
  if (!ref) ImGui::EndDisabled();
  g.view.mode = ViewMode(mode);
  if (g.view.mode == ViewMode::split) ImGui::SliderFloat("split", &g.view.split, 0, 1);
  ImGui::Checkbox("accumulate frames", &g.view.accumulate);
  help_tooltip("on: the progressive mean since the last change; off: each frame's raw output");
  ImGui::SameLine();
  if (ImGui::Checkbox("pause", &g.paused)) g.session.set_paused(g.paused);
  static const float scales[] = {1, 0.5f, 0.25f};
  static const char* scale_names[] = {"1", "1/2", "1/4"};
  int si = g.session.scale() == 1 ? 0 : g.session.scale() == 0.5f ? 1 : 2;
  if (ImGui::Combo("render scale", &si, scale_names, 3)) g.session.set_scale(scales[si]);
  help_tooltip("render at this fraction of film.width x film.height");
  float budget = float(g.pacer.budget() * 100);
  if (ImGui::SliderFloat("redraw budget %", &budget, 0.1f, 100, "%.1f", ImGuiSliderFlags_Logarithmic)) g.pacer.set_budget(budget / 100);
  help_tooltip("share of wall time the window may spend redrawing while nothing moves: each redraw takes CPU from the "
               "renderer (software OpenGL: 10-20 ms); 100 = show every frame. Input always redraws.");
  ImGui::SameLine();
  ImGui::Text("%.1f ms", g.pacer.cost_s() * 1000);
  reference_controls(g);
}

void camera_controls(Gui& g) {
  CameraController& cam = g.session.camera();
  int mode = int(cam.mode());
  ImGui::RadioButton("orbit", &mode, 0);
  ImGui::SameLine();
  ImGui::RadioButton("fly", &mode, 1);
  cam.set_mode(CameraMode(mode));
  ImGui::SameLine();
  if (ImGui::Button("reset")) cam.reset(), g.session.camera_moved();
  if (ImGui::Button(g.session.recording() ? "stop recording" : "record")) g.session.record(!g.session.recording());
  ImGui::SameLine();
  ImGui::Text("%zu keys", g.session.recorded_keys());
  ImGui::SameLine();
  if (ImGui::Button("play")) {
    try {
      g.session.play_camera_path();
    } catch (const std::exception& e) {
      g.say(e.what(), true);
    }
  }
  help_tooltip("plays render.camera_path (or the recorded path) over render.frames frames, as `restir render` would");
  ImGui::InputText("##campath", g.camera_path, sizeof g.camera_path);
  ImGui::SameLine();
  if (ImGui::Button("save path")) {
    try {
      g.session.save_camera_path(g.camera_path);
      g.say(std::string("saved ") + g.camera_path);
    } catch (const std::exception& e) {
      g.say(e.what(), true);
    }
  }
}

void file_controls(Gui& g) {
  ImGui::InputText("##shot", g.screenshot_path, sizeof g.screenshot_path);
  ImGui::SameLine();
  if (ImGui::Button("screenshot")) {
    try {
      g.save_screenshot(g.screenshot_path);
      g.say(std::string("saved ") + g.screenshot_path + ".exr/.png/.json");
    } catch (const std::exception& e) {
      g.say(e.what(), true);
    }
  }
  ImGui::InputText("##config", g.config_path, sizeof g.config_path);
  ImGui::SameLine();
  if (ImGui::Button("save config")) {
    try {
      g.session.save_config(g.config_path);
      g.say(std::string("saved ") + g.config_path);
    } catch (const std::exception& e) {
      g.say(e.what(), true);
    }
  }
}

void option_controls(Gui& g) {
  const auto values = option_values(g.session.options());  // the same order as option_widgets()
  const auto& widgets = option_widgets();
  std::string group;
  bool open = false;
  for (size_t i = 0; i < widgets.size() && i < values.size(); ++i) {
    const OptionWidget& w = widgets[i];
    if (w.group != group) {
      if (open) ImGui::TreePop();
      group = w.group;
      open = ImGui::TreeNodeEx(group.c_str(), group == "general" || group == "output" ? ImGuiTreeNodeFlags_DefaultOpen : 0);
    }
    if (!open) continue;
    std::string value;
    if (option_widget(w, values[i].second, value)) {
      try {
        g.session.set(w.key, value);
        g.say(w.key + " = " + value);
      } catch (const std::exception& e) {
        g.say(e.what(), true);
      }
    }
    help_tooltip(w.help);
  }
  if (open) ImGui::TreePop();
}

}  // namespace

void draw_panels(Gui& g, float width) {
  ImGuiIO& io = ImGui::GetIO();
  ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - width, 0));
  ImGui::SetNextWindowSize(ImVec2(width, io.DisplaySize.y));
  ImGui::Begin("restir view", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
  ImGui::PushItemWidth(width * 0.5f);
  readouts(g);
  const std::string err = g.session.error();
  if (!err.empty()) {
    ImGui::TextColored(ImVec4(1, 0.3f, 0.3f, 1), "render stopped: %s", err.c_str());
    if (ImGui::Button("retry")) g.session.clear_error();
  }
  if (!g.status.empty()) {
    ImGui::PushTextWrapPos(0);
    if (g.status_error) ImGui::TextColored(ImVec4(1, 0.3f, 0.3f, 1), "%s", g.status.c_str());
    else ImGui::TextUnformatted(g.status.c_str());
    ImGui::PopTextWrapPos();
  }
  if (ImGui::CollapsingHeader("view", ImGuiTreeNodeFlags_DefaultOpen)) view_controls(g);
  if (ImGui::CollapsingHeader("camera", ImGuiTreeNodeFlags_DefaultOpen)) camera_controls(g);
  if (ImGui::CollapsingHeader("save", ImGuiTreeNodeFlags_DefaultOpen)) file_controls(g);
  if (ImGui::CollapsingHeader("options", ImGuiTreeNodeFlags_DefaultOpen)) option_controls(g);
  ImGui::PopItemWidth();
  ImGui::End();
}

}  // namespace rl::viewer
