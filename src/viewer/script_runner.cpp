#include "viewer/script_runner.h"

#include <stdexcept>

namespace rl::viewer {

std::string ScriptRunner::where() const {
  const size_t i = next_ > 0 ? next_ - 1 : 0;
  return i < script_.commands.size() ? script_.where(script_.commands[i]) : script_.path;
}

ScriptRunner::Step ScriptRunner::step(const std::function<void(const std::string&)>& screenshot) {
  if (waiting_) {
    if (!(waiting_reference_ ? session_.reference_done() : session_.frames_done())) return Step::waiting;
    waiting_ = false;
    if (waiting_reference_) session_.poll_reference();
    const std::string err = session_.error();
    if (!err.empty()) throw ScriptError(where() + ": render failed: " + err);
  }
  while (next_ < script_.commands.size()) {
    const ScriptCommand& c = script_.commands[next_++];
    try {
      if (c.verb == "quit") {
        next_ = script_.commands.size();
        return Step::done;
      }
      run(c, screenshot);
    } catch (const std::exception& e) {
      throw ScriptError(script_.where(c) + ": " + e.what());
    }
    if (c.verb == "frames" || (c.verb == "reference" && c.args[0] == "wait")) {
      waiting_ = true;
      waiting_reference_ = c.verb == "reference";
      return Step::waiting;
    }
    if (c.verb == "screenshot") return Step::drawn;
  }
  return Step::done;
}

void ScriptRunner::run(const ScriptCommand& c, const std::function<void(const std::string&)>& screenshot) {
  const auto& a = c.args;
  float f[3] = {0, 0, 0};
  if (c.verb == "set") {
    session_.set(a[0], a[1]);
  } else if (c.verb == "frames") {
    int n = 0;
    parse_int(a[0], n);
    session_.render_frames(n);
  } else if (c.verb == "screenshot") {
    screenshot(a[0]);
  } else if (c.verb == "view") {
    const ViewMode m = a[0] == "error" ? ViewMode::error : a[0] == "split" ? ViewMode::split : ViewMode::radiance;
    if (m != ViewMode::radiance && !session_.reference())
      throw ScriptError("view " + a[0] + (session_.has_reference() ? ": the --reference image is not the film's size"
                                                                    : ": needs --reference FILE.exr"));
    view_.mode = m;
  } else if (c.verb == "split") {
    parse_float(a[0], view_.split);
  } else if (c.verb == "accumulate") {
    view_.accumulate = a[0] == "on";
  } else if (c.verb == "scale") {
    parse_float(a[0], f[0]);
    session_.set_scale(f[0]);
  } else if (c.verb == "camera") {
    CameraController& cam = session_.camera();
    for (size_t i = 1; i < a.size() && i <= 3; ++i) parse_float(a[i], f[i - 1]);
    if (a[0] == "orbit") cam.rotate(f[0], f[1]);
    else if (a[0] == "move") cam.move(Vec3(f[0], f[1], f[2]));
    else if (a[0] == "reset") cam.reset();
    else if (a[0] == "mode") cam.set_mode(a[1] == "fly" ? CameraMode::fly : CameraMode::orbit);
    if (a[0] != "mode") session_.camera_moved();
  } else if (c.verb == "record") {
    if (a[0] == "save") session_.save_camera_path(a[1]);
    else session_.record(a[0] == "start");
  } else if (c.verb == "reference") {
    ReferenceSettings r = session_.reference_settings();
    if (a[0] == "wait") {
      if (!r.on || r.target_spp == 0) throw ScriptError("reference wait: no background reference with a target (reference on SPP)");
      return;
    }
    if (session_.has_reference_file()) throw ScriptError("reference: the viewer has a --reference image");
    r.on = a[0] == "on";
    if (r.on) r.target_spp = 4096;
    if (a.size() == 2) parse_int(a[1], r.target_spp);
    session_.set_reference(r);
  } else if (c.verb == "save-config") {
    session_.save_config(a[0]);
  }
}

}  // namespace rl::viewer
