// The viewer's state without its window: the scene, the options as the user set them, a worker
// thread that renders frames with one persistent FrameRenderer (so ReSTIR's history carries over),
// the progressive accumulation, the camera, and the files a session writes (screenshots, configs,
// camera paths). The GUI (viewer/gui/) draws it and feeds it input; the script runner drives
// it without a user. Threads: every public function is for the UI thread; the worker only sees
// what they hand over under the lock.
#pragma once
#include <atomic>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "image/image.h"
#include "frame/options.h"
#include "frame/render.h"
#include "frame/stage_times.h"
#include "scene/scene.h"
#include "viewer/camera_controller.h"
#include "viewer/display.h"
#include "viewer/option_model.h"

namespace rl::viewer {

// A viewer action that cannot be carried out: no window, no frame rendered yet, no camera keys,
// a render that failed under --bench.
struct ViewerError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class BackgroundReference;

// `restir view` arguments (app/main.cpp fills them from the command line).
struct ViewArgs {
  std::string scene, integrator, config, script, reference;
  std::vector<std::string> sets;
  float scale = 1;  // render at this fraction of film.width x film.height: 1, 0.5 or 0.25
  int spp = 0;      // --spp (0: the viewer's default of 1, see viewer_options)
  int bench = 0;    // --bench N: N frames bare, then N through the viewer loop; print the ratio
  int width = 0, height = 0;  // window size (0: fit the image)
  bool quiet = false;
  bool background_reference = false;  // --background-reference: start with it on
  float redraw_budget = 0.03f;  // --redraw-budget: the window's share of wall time for redraws (DrawPacer)
};

// The background reference's settings (background_reference.h), set from the UI thread.
struct ReferenceSettings {
  bool on = false;
  int target_spp = 4096;  // it stops there (0: never)
  // Its share of the render time while the viewer renders frames (it takes all of it while the
  // viewer is paused or, in a script, between `frames` commands).
  float share = 0.25f;
};

// The options of a viewer session: defaults < the scene file < 1 spp per frame (the viewer
// accumulates frames instead) < --config < --integrator / --spp < --set. Validated.
Options viewer_options(const ViewArgs& a, const Scene& scene);

// The numbers of the latest frame.
struct FrameReadout {
  double ms = 0;
  StageTimes stages;
  int accumulated = 0;  // frames in the progressive mean
  int frame = 0;        // frame index since the integrator was (re)created
  int width = 0, height = 0;
  long long serial = 0;  // frames rendered by the session before this one + 1
  int reference_spp = 0;           // samples per pixel of the background reference (0: none yet)
  long long reference_serial = 0;  // changes with each new background reference image
};

class Session {
 public:
  explicit Session(const ViewArgs& a);  // loads the scene, options and reference; throws on bad input
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  // Starts the worker; `wake` is called (from the worker) after each frame and on an error.
  void start(std::function<void()> wake);
  void stop();

  const Options& options() const { return options_; }  // film size before the render scale
  Options effective_options() const;                   // what the worker renders (scaled film)
  const Scene& scene() const { return scene_; }
  const ViewArgs& args() const { return args_; }
  // Applies key=value if valid (else throws OptionError, nothing changes) and hands the worker
  // what the change invalidates: nothing for output.*, the thread count, or a restart.
  Effect set(const std::string& key, const std::string& value);
  void set_scale(float s);
  float scale() const { return scale_; }
  void set_paused(bool p);
  bool paused() const { return paused_; }

  CameraController& camera() { return camera_; }
  void camera_moved();  // after changing camera(): accumulation restarts, history is reprojected
  // Plays render.camera_path (or, if it is empty, the recorded path) from frame 0 through
  // render.frames frames exactly as `restir render` would, then holds its last key.
  void play_camera_path();
  bool playing() const;
  void record(bool on);
  bool recording() const { return recording_; }
  size_t recorded_keys() const;
  void save_camera_path(const std::string& path) const;
  // The options as a --config JSON; a moved camera goes with it as PATH.camera.json
  // (render.camera_path), so the file reproduces the view.
  void save_config(const std::string& path) const;

  // Script mode: render exactly n more frames, then idle (until the next call); done() tells.
  void render_frames(int n);
  bool frames_done() const;
  long long frames_completed() const;  // frames rendered since the session started
  void wait_frames_done() const;

  // Copies the shown image (mean or last frame) and its numbers when a frame arrived since the
  // last call, or always with `force`. False: nothing new.
  bool take_frame(bool accumulate, bool force, Image& hdr, FrameReadout& r);
  // True when take_frame has something new (a frame or a background reference pass).
  bool frame_waiting() const;
  // The frame times (ms) of every frame rendered since the last call, oldest first: the window
  // may show fewer frames than the worker renders (DrawPacer), the plot and fps count them all.
  std::vector<double> take_frame_times();
  std::string error() const;  // the worker's error (it stops rendering); empty when fine
  void clear_error();

  // The reference the metrics and views compare against: the --reference image at the render's
  // size (downsampled at a render scale < 1), else the background reference once it has a pass
  // of the current view; null without one or when the --reference is not the film's size.
  const Image* reference() const;
  bool has_reference() const { return reference_.has_value() || reference_settings_.on; }
  bool has_reference_file() const { return reference_.has_value(); }

  // The background reference (background_reference.h). Changing it hands the worker the new
  // settings; turning it off drops its image.
  void set_reference(const ReferenceSettings& s);
  const ReferenceSettings& reference_settings() const { return reference_settings_; }
  // Copies a new background reference image from the worker, if any (take_frame does too); true
  // when it changed. UI thread.
  bool poll_reference();
  int reference_spp() const { return ui_reference_spp_; }
  // The background reference's own relMSE (BackgroundReference::own_rel_mse) as of the image
  // reference() shows; -1 for a --reference file (its error is unknown) or before its second pass.
  double reference_own_rel_mse() const { return reference_.has_value() ? -1 : ui_reference_rel_mse_; }
  // True when the background reference has reached its target for the current view (or failed:
  // see error()).
  bool reference_done() const;
  void wait_reference_done() const;
  // Writes BASE.exr (hdr), BASE.png (ldr), BASE.json (sidecar: options, camera, view, metrics).
  void screenshot(const std::string& base, const Image& hdr, const Image& ldr, const FrameReadout& r,
                  const std::string& view_json) const;
  // The inputs no output may overwrite (scene files, --config, camera path, reference).
  std::vector<std::string> inputs() const;

 private:
  void worker();
  // One turn of the worker: what take_turn handed it under m_ (defined in session.cpp).
  struct Turn;
  bool take_turn(Turn& t, CameraKey& camera, PathKey& path_key);  // false: quit
  void view_turn(const Turn& t, const CameraKey& camera, const PathKey& path_key,
                 std::unique_ptr<FrameRenderer>& renderer, Image& frame);
  void push_restart();
  void reference_turn(const Options& o, const CameraKey& camera, int frame);
  bool aim_reference(const Options& o, const CameraKey& camera, int frame);
  void reference_restarted();  // under m_
  bool copy_reference();       // under m_, UI thread
  std::string reference_key(const Options& o) const;

  ViewArgs args_;
  Scene scene_;
  Options defaults_;  // the scene's hints over the defaults (the background reference's base)
  Options options_;
  float scale_ = 1;
  std::optional<Image> reference_;
  mutable std::optional<Image> scaled_reference_;
  CameraController camera_;
  bool recording_ = false;
  bool paused_ = false;
  ReferenceSettings reference_settings_;
  Image ui_reference_;  // the UI thread's copy of the background reference
  int ui_reference_spp_ = 0;
  double ui_reference_rel_mse_ = -1;
  long long ui_reference_serial_ = 0;

  // Shared with the worker, under m_.
  mutable std::mutex m_;
  mutable std::condition_variable cv_;     // the worker waits on it for work
  mutable std::condition_variable done_cv_;  // script mode waits on it for frames
  std::atomic<bool> abort_{false};  // cut the frame being rendered (a restart or quit is pending)
  std::atomic<bool> reference_abort_{false};  // cut the reference pass (its view changed)
  bool quit_ = false, restart_ = true, threads_changed_ = false, camera_changed_ = false, new_frame_ = false;
  Options pending_;
  CameraKey pending_camera_;
  PathKey pending_path_key_;
  std::optional<Camera> play_;  // a camera path being played
  int play_frames_ = 0, play_index_ = 0;
  long long budget_ = -1, done_ = 0;  // frames to render (-1: no limit), frames rendered
  bool worker_recording_ = false;
  std::vector<PathKey> recorded_;
  Accumulation accum_;  // the frames since the last change (written by the worker)
  FrameReadout shared_readout_;
  std::vector<double> frame_times_;
  // The background reference: settings handed over, progress reported back.
  ReferenceSettings worker_reference_;
  bool reference_full_ = false;  // it reached its target for the view it was last aimed at
  Image shared_reference_;
  int shared_reference_spp_ = 0;
  double shared_reference_rel_mse_ = -1;
  long long reference_serial_ = 0;
  double reference_ms_ = 0, view_ms_ = 0;  // render time of each since the reference restarted
  int view_frame_ = 0;                     // the animation frame of the last frame shown
  std::unique_ptr<BackgroundReference> background_;  // the worker's
  std::string error_;
  std::function<void()> wake_;
  std::thread thread_;
};

}  // namespace rl::viewer
