#include "viewer/session.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <utility>
#include <nlohmann/json.hpp>

#include "core/build_info.h"
#include "core/output_guard.h"
#include "image/image_io.h"
#include "frame/integrator.h"
#include <cstdio>

#include "scene/camera.h"
#include "scene/loader.h"
#include "viewer/background_reference.h"

namespace rl::viewer {

Options viewer_options(const ViewArgs& a, const Scene& scene) {
  Options o;
  apply_scene_hints(o, scene.hints);
  // A scene file's pixel count is for a converged still (the Cornell box asks for 64 spp): the
  // viewer accumulates frames instead, so it starts at one sample per pixel per frame.
  o.render.spp = 1;
  if (!a.config.empty()) apply_options_file(o, a.config);
  if (!a.integrator.empty()) set_option(o, "integrator", a.integrator);
  if (a.spp > 0) set_option(o, "render.spp", std::to_string(a.spp));
  for (const auto& s : a.sets) set_option_assignment(o, s);
  for (const std::string& n : fit_defaults_to_integrator(o, /*sequence=*/false)) std::fprintf(stderr, "note: %s\n", n.c_str());
  validate_options(o);
  find_integrator(o.integrator);
  return o;
}

namespace {

// Thrown from the progress callback to cut a frame short (Session::abort_).
struct FrameAborted {};

Camera initial_camera(const Scene& scene) {
  Camera c = scene.camera;
  if (c.keys.empty()) c.keys.push_back(CameraKey{});
  return c;
}

CameraKey key_of(const PathKey& p) {
  CameraKey k;
  k.fov_degrees = p.fov;
  if (look_at(p.eye, p.target, p.up, k.camera_from_world) && p.mirror)
    k.camera_from_world = scale(Vec3(-1, 1, 1)) * k.camera_from_world;
  return k;
}

}  // namespace

Session::Session(const ViewArgs& a)
    : args_(a),
      scene_(load_scene(a.scene)),
      options_(viewer_options(a, scene_)),
      camera_(initial_camera(scene_).keys.front(), scene_.bounds()) {
  set_scale(a.scale);
  // Its size is checked against the render's when it is used: the film size is an option that
  // may change during the session.
  if (!a.reference.empty()) reference_ = read_image(a.reference);
  apply_scene_hints(defaults_, scene_.hints);
  pending_ = effective_options();
  pending_camera_ = camera_.key();
  pending_path_key_ = camera_.path_key();
  if (a.background_reference) {
    reference_settings_.on = true;
    worker_reference_ = reference_settings_;
  }
}

Session::~Session() { stop(); }

void Session::start(std::function<void()> wake) {
  wake_ = std::move(wake);
  thread_ = std::thread([this] { worker(); });
}

void Session::stop() {
  {
    std::lock_guard lk(m_);
    quit_ = true;
    abort_ = true;
    reference_abort_ = true;
  }
  cv_.notify_all();
  if (thread_.joinable()) thread_.join();
}

Options Session::effective_options() const {
  Options o = options_;
  o.film.width = std::max(1, int(std::lround(double(o.film.width) * scale_)));
  o.film.height = std::max(1, int(std::lround(double(o.film.height) * scale_)));
  return o;
}

void Session::push_restart() {
  {
    std::lock_guard lk(m_);
    pending_ = effective_options();
    restart_ = true;
    abort_ = true;  // the frame being rendered is of the old options: drop it
    reference_full_ = false;  // the worker re-aims the reference
  }
  cv_.notify_all();
}

std::string Session::reference_key(const Options& o) const {
  return options_to_json(background_reference_options(defaults_, o), -1);
}

Effect Session::set(const std::string& key, const std::string& value) {
  const std::string before = reference_key(options_);
  const Effect e = apply_option(options_, key, value);
  if (e == Effect::restart) {
    // A change the background reference depends on cuts its pass short; ReSTIR's options do not.
    if (reference_key(options_) != before) reference_abort_ = true;
    push_restart();
  } else if (e == Effect::threads) {
    {
      std::lock_guard lk(m_);
      pending_.render.threads = options_.render.threads;
      threads_changed_ = true;
    }
    cv_.notify_all();
  }
  return e;
}

void Session::set_scale(float s) {
  if (s != 1 && s != 0.5f && s != 0.25f) throw OptionError(fmt::format("render scale {} is not one of 1, 0.5, 0.25", s));
  if (s == scale_) return;
  scale_ = s;
  scaled_reference_.reset();
  reference_abort_ = true;
  push_restart();
}

const Image* Session::reference() const {
  const Options o = effective_options();
  if (!reference_) {
    const bool fits = ui_reference_.width == o.film.width && ui_reference_.height == o.film.height;
    return reference_settings_.on && ui_reference_spp_ > 0 && fits ? &ui_reference_ : nullptr;
  }
  const Image* ref = &*reference_;
  if (scale_ != 1) {
    // The reference at the render's size: box-filtered over the factor's pixel blocks, which is
    // what a render at that size converges to, up to the pixel filter's footprint.
    if (!scaled_reference_) scaled_reference_ = downsample(*reference_, int(std::lround(1 / scale_)));
    ref = &*scaled_reference_;
  }
  return ref->width == o.film.width && ref->height == o.film.height ? ref : nullptr;
}

void Session::set_paused(bool p) {
  {
    std::lock_guard lk(m_);
    paused_ = p;
  }
  cv_.notify_all();
}

void Session::camera_moved() {
  {
    std::lock_guard lk(m_);
    pending_camera_ = camera_.key();
    pending_path_key_ = camera_.path_key();
    camera_changed_ = true;
    play_.reset();
    reference_full_ = false;
  }
  reference_abort_ = true;
  cv_.notify_all();
}

void Session::play_camera_path() {
  Camera path = initial_camera(scene_);
  if (!options_.render.camera_path.empty()) {
    load_camera_path(options_.render.camera_path, path);
  } else {
    std::lock_guard lk(m_);
    if (recorded_.empty()) throw ViewerError("play: no camera path: set render.camera_path or record one");
    path.keys.clear();
    for (const PathKey& k : recorded_) path.keys.push_back(key_of(k));
  }
  {
    std::lock_guard lk(m_);
    play_ = std::move(path);
    play_frames_ = options_.render.frames;
    play_index_ = 0;
    pending_ = effective_options();
    restart_ = true;  // from frame 0 with no history, as `restir render` starts
    abort_ = true;
    reference_full_ = false;
  }
  reference_abort_ = true;
  cv_.notify_all();
}

bool Session::playing() const {
  std::lock_guard lk(m_);
  return play_ && play_index_ < play_frames_;
}

void Session::record(bool on) {
  recording_ = on;
  std::lock_guard lk(m_);
  if (on && !worker_recording_) recorded_.clear();
  worker_recording_ = on;
}

size_t Session::recorded_keys() const {
  std::lock_guard lk(m_);
  return recorded_.size();
}

std::vector<std::string> Session::inputs() const {
  std::vector<std::string> in = scene_.input_files;
  if (in.empty()) in.push_back(args_.scene);
  if (!args_.config.empty()) in.push_back(args_.config);
  if (!args_.reference.empty()) in.push_back(args_.reference);
  if (!options_.render.camera_path.empty()) in.push_back(options_.render.camera_path);
  return in;
}

void Session::save_camera_path(const std::string& path) const {
  std::vector<PathKey> keys;
  {
    std::lock_guard lk(m_);
    keys = recorded_;
  }
  if (keys.empty()) throw ViewerError("record save '" + path + "': no camera keys recorded (record start, render, record stop)");
  check_outputs({{path, "camera path", {".json"}}}, inputs());
  write_text_file_atomic(path, camera_path_json(keys));
}

void Session::save_config(const std::string& path) const {
  Options o = options_;
  const PathKey now = camera_.path_key();
  const PathKey home = CameraController(initial_camera(scene_).keys.front(), scene_.bounds()).path_key();
  const bool moved = length(now.eye - home.eye) > 0 || length(now.target - home.target) > 0;
  std::vector<OutputFile> outs = {{path, "config", {".json"}}};
  std::string camera_file;
  if (moved) {
    camera_file = std::filesystem::path(path).replace_extension(".camera.json").string();
    outs.push_back({camera_file, "camera path of " + path, {".json"}});
    o.render.camera_path = camera_file;
  }
  check_outputs(outs, inputs());
  if (moved) write_text_file_atomic(camera_file, camera_path_json({now}));
  write_text_file_atomic(path, options_to_json(o) + "\n");
}

void Session::render_frames(int n) {
  {
    std::lock_guard lk(m_);
    budget_ = done_ + n;
  }
  cv_.notify_all();
}

bool Session::frames_done() const {
  std::lock_guard lk(m_);
  return !error_.empty() || (budget_ >= 0 && done_ >= budget_);
}

long long Session::frames_completed() const {
  std::lock_guard lk(m_);
  return done_;
}

void Session::wait_frames_done() const {
  std::unique_lock lk(m_);
  done_cv_.wait(lk, [&] { return !error_.empty() || (budget_ >= 0 && done_ >= budget_); });
}

bool Session::take_frame(bool accumulate, bool force, Image& hdr, FrameReadout& r) {
  // One lock for both: a frame and the reference it is compared with are of the same view.
  std::lock_guard lk(m_);
  const bool reference = copy_reference();
  if (!new_frame_ && !force && !reference) return false;
  new_frame_ = false;
  hdr = accum_.shown(accumulate);
  r = shared_readout_;
  r.reference_spp = ui_reference_spp_;
  r.reference_serial = ui_reference_serial_;
  return true;
}

bool Session::frame_waiting() const {
  std::lock_guard lk(m_);
  return new_frame_ || reference_serial_ != ui_reference_serial_;
}

std::vector<double> Session::take_frame_times() {
  std::lock_guard lk(m_);
  return std::exchange(frame_times_, {});
}

void Session::set_reference(const ReferenceSettings& s) {
  if (s.target_spp < 0 || s.target_spp > (1 << 24)) throw OptionError(fmt::format("reference target {} spp is not in [0, 16777216]", s.target_spp));
  if (!(s.share > 0 && s.share < 1)) throw OptionError(fmt::format("reference share {} is not in (0, 1)", s.share));
  reference_settings_ = s;
  {
    std::lock_guard lk(m_);
    worker_reference_ = s;
    reference_full_ = false;
  }
  if (!s.on) reference_abort_ = true;
  cv_.notify_all();
}

bool Session::poll_reference() {
  std::lock_guard lk(m_);
  return copy_reference();
}

bool Session::copy_reference() {
  if (reference_serial_ == ui_reference_serial_) return false;
  if (shared_reference_spp_ > 0) ui_reference_ = shared_reference_;
  ui_reference_spp_ = shared_reference_spp_;
  ui_reference_rel_mse_ = shared_reference_rel_mse_;
  ui_reference_serial_ = reference_serial_;
  return true;
}

bool Session::reference_done() const {
  std::lock_guard lk(m_);
  return !error_.empty() || !worker_reference_.on || reference_full_;
}

void Session::wait_reference_done() const {
  std::unique_lock lk(m_);
  done_cv_.wait(lk, [&] { return !error_.empty() || !worker_reference_.on || reference_full_; });
}

std::string Session::error() const {
  std::lock_guard lk(m_);
  return error_;
}

void Session::clear_error() {
  {
    std::lock_guard lk(m_);
    error_.clear();
    restart_ = true;
    pending_ = effective_options();
  }
  cv_.notify_all();
}

void Session::screenshot(const std::string& base, const Image& hdr, const Image& ldr, const FrameReadout& r,
                         const std::string& view_json) const {
  if (hdr.empty()) throw ViewerError("screenshot '" + base + "': no frame rendered yet");
  std::filesystem::path p(base);
  if (p.extension() == ".exr" || p.extension() == ".png") p.replace_extension();
  const std::string stem = p.string();
  check_outputs({{stem + ".exr", "screenshot", {".exr"}},
                 {stem + ".png", "screenshot", {".png"}},
                 {stem + ".json", "sidecar of " + stem + ".exr", {".json"}, false, true}},
                inputs());
  const std::string config = options_to_json(effective_options(), -1);
  write_exr(stem + ".exr", hdr, {{"restir.version", rl::build_id()}, {"restir.scene", args_.scene}, {"restir.config", config}});
  write_png(stem + ".png", ldr);
  nlohmann::ordered_json side;
  side[kSidecarMarker] = 1;
  side["version"] = rl::build_id();
  side["scene"] = args_.scene;
  side["config"] = nlohmann::ordered_json::parse(config);
  const PathKey k = camera_.path_key();
  side["camera"] = nlohmann::ordered_json::parse(camera_path_json({k}))["keys"][0];
  side["view"] = nlohmann::ordered_json::parse(view_json);
  side["frames_accumulated"] = r.accumulated;
  side["frame_ms"] = r.ms;
  nlohmann::ordered_json stages = nlohmann::ordered_json::object();
  for (const auto& [name, ms] : r.stages.ms) stages[name] = ms;
  side["stage_ms"] = std::move(stages);
  nlohmann::ordered_json rays = nlohmann::ordered_json::object();  // as `restir render`'s sidecar
  for (const auto& [name, c] : r.stages.rays) rays[name] = {{"closest", c.closest}, {"any", c.any}, {"queued", c.queued}};
  side["pixels"] = size_t(r.width) * size_t(r.height);
  side["stage_rays"] = std::move(rays);
  write_text_file_atomic(stem + ".json", side.dump(2) + "\n");
}

// Aims the background reference at the view the viewer shows (worker thread; true: it
// restarted). The caller publishes the restart under the lock (reference_restarted).
bool Session::aim_reference(const Options& o, const CameraKey& camera, int frame) {
  if (!background_) background_ = std::make_unique<BackgroundReference>(scene_, defaults_);
  return background_->aim(o, camera, frame);
}

void Session::reference_restarted() {
  reference_ms_ = view_ms_ = 0;  // the time shares restart with the reference
  shared_reference_spp_ = 0;      // no metrics against the old view's image
  shared_reference_rel_mse_ = -1;
  reference_full_ = false;
  ++reference_serial_;
}

// One pass of the background reference (worker thread).
void Session::reference_turn(const Options& o, const CameraKey& camera, int frame) {
  int target = 0;
  {
    std::lock_guard lk(m_);
    target = worker_reference_.target_spp;
  }
  if (aim_reference(o, camera, frame)) {
    std::lock_guard lk(m_);
    reference_restarted();
  }
  BackgroundReference& bg = *background_;
  const bool full = target > 0 && bg.spp() >= target;
  double ms = 0;
  // Cut short only by a change of its own view or a quit (both set reference_abort_); abort_
  // is about the viewer's frame.
  if (!full) ms = bg.pass([this](int, int) {
    if (reference_abort_) throw FrameAborted();
  });
  std::lock_guard lk(m_);
  reference_ms_ += ms;
  if (!full) {
    shared_reference_ = bg.mean();
    shared_reference_spp_ = bg.spp();
    shared_reference_rel_mse_ = bg.own_rel_mse();
    ++reference_serial_;
  }
  reference_full_ = target > 0 && bg.spp() >= target;
}

struct Session::Turn {
  bool restart = false, threads = false, moved = false;  // what changed for the view since its last frame
  bool reference = false;                                // the background reference's turn
  bool reference_on = false;
  Options o;
};

// Waits for work and takes what the UI handed over: the options, the camera (the played path's
// where one plays) and, on the view's turn, the changes since its last frame.
bool Session::take_turn(Turn& t, CameraKey& camera, PathKey& path_key) {
  std::unique_lock lk(m_);
  auto view_wanted = [&] { return !paused_ && (budget_ < 0 || done_ < budget_); };
  auto reference_wanted = [&] { return worker_reference_.on && !reference_full_; };
  cv_.wait(lk, [&] { return quit_ || (error_.empty() && (view_wanted() || reference_wanted())); });
  if (quit_) return false;
  // The reference's turn when the viewer renders nothing, or when it is behind its share of
  // the render time.
  const double share = worker_reference_.share;
  t.reference = reference_wanted() && (!view_wanted() || reference_ms_ <= share * (reference_ms_ + view_ms_));
  t.reference_on = worker_reference_.on;
  t.o = pending_;
  if (t.reference) {
    reference_abort_ = false;
    camera = play_ ? play_->at_frame(std::min(play_index_, play_frames_ - 1), play_frames_) : pending_camera_;
  } else {
    std::swap(t.restart, restart_);
    abort_ = false;  // a change from here on aborts the frame below
    std::swap(t.threads, threads_changed_);
    std::swap(t.moved, camera_changed_);
    camera = pending_camera_;
    path_key = pending_path_key_;
    if (play_ && play_index_ < play_frames_) {
      camera = play_->at_frame(play_index_, play_frames_);
      t.moved = play_index_++ > 0;
    } else if (play_) {
      camera = play_->at_frame(play_frames_ - 1, play_frames_);  // the path ended: hold its last key
    }
  }
  return true;
}

// Renders one frame of the view and publishes it (worker thread).
void Session::view_turn(const Turn& t, const CameraKey& camera, const PathKey& path_key,
                        std::unique_ptr<FrameRenderer>& renderer, Image& frame) {
  const Options& o = t.o;
  if (!renderer) renderer = std::make_unique<FrameRenderer>(scene_, o);
  else if (t.restart) renderer->reset(o);
  else if (t.threads) renderer->set_threads(o.render.threads);
  if (t.restart || t.moved) {
    std::lock_guard lk(m_);
    accum_.reset();
  }
  StageTimes stages;
  // A restart or quit requested mid-frame ends the frame at the integrator's next progress
  // report (a tile or a wave) instead of after it: a slow frame does not delay the change.
  const double ms = renderer->render_frame(camera, o.render.frames, frame, &stages, [this](int, int) {
    if (abort_) throw FrameAborted();
  });
  // A reference of another view must not be compared with this frame: re-aim it first.
  const bool reference_moved = t.reference_on && aim_reference(o, camera, renderer->frames_rendered() - 1);
  std::lock_guard lk(m_);
  // With denoise.method set, the view (and its metrics) is the denoised frame (docs/denoise.md).
  accum_.add(renderer->denoised().empty() ? frame : renderer->denoised());  // under the lock: the UI copies what it shows straight from it
  if (reference_moved) reference_restarted();
  view_frame_ = renderer->frames_rendered() - 1;
  view_ms_ += ms;
  frame_times_.push_back(ms);
  if (frame_times_.size() > 4096) frame_times_.erase(frame_times_.begin(), frame_times_.end() - 4096);
  if (worker_recording_) recorded_.push_back(path_key);
  shared_readout_ = {ms, std::move(stages), accum_.count(), renderer->frames_rendered() - 1, frame.width, frame.height, done_ + 1};
  new_frame_ = true;
  ++done_;
}

void Session::worker() {
  std::unique_ptr<FrameRenderer> renderer;
  Image frame;
  CameraKey camera = pending_camera_;
  PathKey path_key = pending_path_key_;
  for (;;) {
    Turn t;
    if (!take_turn(t, camera, path_key)) return;
    try {
      if (t.reference) reference_turn(t.o, camera, view_frame_);
      else view_turn(t, camera, path_key, renderer, frame);
    } catch (const FrameAborted&) {
      // Only a pending restart, view change or quit aborts: the next turn replaces the
      // integrator, whose state is now half a frame's (the BVH and lights stay), re-aims the
      // reference, or leaves.
      continue;
    } catch (const std::exception& e) {
      std::lock_guard lk(m_);
      error_ = t.reference ? std::string("background reference: ") + e.what() : e.what();
      if (t.reference) background_.reset();
      else renderer.reset();  // rebuilt from the pending options once the error is cleared
    }
    done_cv_.notify_all();
    if (wake_) wake_();
  }
}

}  // namespace rl::viewer
