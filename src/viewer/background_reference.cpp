#include "viewer/background_reference.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "scene/animation.h"

namespace rl::viewer {

uint64_t reference_seed(uint64_t viewer_seed) { return viewer_seed ^ 0x5245464552454e43ull; }  // "REFERENC"

BackgroundReference::BackgroundReference(const Scene& scene, Options defaults) : rest_(scene), defaults_(std::move(defaults)) {
  for (const Animation& a : scene.animations)
    if (!a.keys.empty()) last_key_frame_ = std::max(last_key_frame_, a.keys.back().frame);
}

BackgroundReference::~BackgroundReference() = default;

Options background_reference_options(const Options& defaults, const Options& viewer) {
  Options r = reference_options(defaults, viewer);
  r.render.spp = 1;
  r.render.frames = 1;
  r.render.seed = reference_seed(viewer.render.seed);
  r.render.backend = viewer.render.backend;  // pt runs on either
  r.render.threads = 0;
  return r;
}

bool BackgroundReference::aim(const Options& viewer, const CameraKey& camera, int frame) {
  Options r = background_reference_options(defaults_, viewer);
  const bool animated = scene_animated(rest_);
  const int pose = animated ? std::clamp(frame, 0, last_key_frame_) : 0;
  std::string key = options_to_json(r, -1);
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) key += fmt::format(" {}", camera.camera_from_world.m[a][b]);
  key += fmt::format(" fov {} pose {}", camera.fov_degrees, pose);
  r.render.threads = viewer.render.threads;  // not part of the key: the image does not depend on it
  if (key == key_) {
    if (renderer_ && r.render.threads != options_.render.threads) renderer_->set_threads(r.render.threads);
    options_.render.threads = r.render.threads;
    return false;
  }
  renderer_.reset();
  frozen_.reset();  // built by the first pass: while the view changes every frame, aiming stays cheap
  pose_ = animated ? pose : -1;
  key_ = std::move(key);
  options_ = r;
  camera_ = camera;
  mean_.reset();
  return true;
}

double BackgroundReference::pass(const std::function<void(int, int)>& progress) {
  if (key_.empty()) throw std::logic_error("BackgroundReference::pass before aim");
  if (pose_ >= 0 && !frozen_) frozen_ = std::make_unique<Scene>(scene_at_frame(rest_, pose_));
  if (!renderer_) renderer_ = std::make_unique<FrameRenderer>(frozen_ ? *frozen_ : rest_, options_);
  Image img;
  // Each pass is the next frame of a static sequence: a new per-frame seed, the same view.
  const double ms = renderer_->render_frame(camera_, options_.render.frames, img, nullptr, progress);
  mean_.add(img);
  const size_t n = img.pixels.size() * 3;
  if (mean_.count() == 1) squares_.assign(n, 0.0);
  const double w = 1.0 / mean_.count();
  for (size_t i = 0; i < n; ++i) {
    const double v = img.pixels[i / 3][int(i % 3)];
    squares_[i] += (v * v - squares_[i]) * w;
  }
  return ms;
}

double BackgroundReference::own_rel_mse() const { return rel_mse_of_mean(mean_.mean(), squares_, mean_.count()); }

double rel_mse_of_mean(const Image& mean, const std::vector<double>& squares, int n) {
  if (n < 2 || squares.size() != mean.pixels.size() * 3 || squares.empty()) return -1;
  double sum = 0;
  for (size_t i = 0; i < squares.size(); ++i) {
    const double m = mean.pixels[i / 3][int(i % 3)];
    const double variance_of_mean = std::max(0.0, squares[i] - m * m) / (n - 1);
    const double den = (m + 0.01) * (m + 0.01);
    if (den > 0 && std::isfinite(variance_of_mean)) sum += variance_of_mean / den;
  }
  return sum / double(squares.size());
}

}  // namespace rl::viewer
