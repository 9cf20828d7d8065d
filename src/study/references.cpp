#include "study/references.h"

#include <array>
#include <cstdlib>
#include <filesystem>
#include <limits>

#include <fmt/format.h>

#include "core/build_info.h"
#include "core/file_lock.h"
#include "core/rng.h"
#include "image/image_io.h"
#include "image/metrics.h"
#include "frame/render.h"
#include "scene/animation.h"
#include "scene/camera.h"
#include "study/results.h"

namespace rl::study {
namespace fs = std::filesystem;

namespace {
Camera camera_of(const Scene& scene, const Options& o) {
  Camera c = scene.camera;
  if (!o.render.camera_path.empty()) load_camera_path(o.render.camera_path, c);
  if (c.keys.empty()) c.keys.push_back(CameraKey{});
  return c;
}

constexpr const char* kHalvesKey = "restir.reference_halves_spp";
constexpr const char* kOwnErrorKey = "restir.reference_relmse";

struct Halves {
  Image mean;
  double own_error = std::numeric_limits<double>::quiet_NaN();
  std::array<int, 2> spp{0, 0};
};

// The reference as two independent renders (references.h): the second half's seed is derived
// from the first, so a study's reference.seed still names the whole reference.
Halves render_halves(const Scene& scene, const Options& o) {
  Halves h;
  const int n = o.render.spp, na = n - n / 2, nb = n / 2;
  h.spp = {na, nb};
  Options a = o, b = o;
  a.render.spp = na;
  b.render.spp = nb;
  b.render.seed = mix64(o.render.seed ^ 0x243f6a8885a308d3ULL) & 0x7fffffffffffffffULL;
  RenderResult ra = render(scene, a, {});
  if (nb == 0) {
    h.mean = std::move(ra.last);
    return h;
  }
  const RenderResult rb = render(scene, b, {});
  h.mean = Image(ra.last.width, ra.last.height);
  Image shifted = h.mean;  // mean + (A − B): rel_mse(shifted, mean) = mean of (A − B)² / (mean² + eps)
  const float wa = float(na) / float(n), wb = float(nb) / float(n);
  for (size_t i = 0; i < h.mean.size(); ++i) {
    h.mean.pixels[i] = ra.last.pixels[i] * wa + rb.last.pixels[i] * wb;
    shifted.pixels[i] = h.mean.pixels[i] + (ra.last.pixels[i] - rb.last.pixels[i]);
  }
  h.own_error = rel_mse(shifted, h.mean) * double(na) * double(nb) / (double(n) * double(n));
  return h;
}

// The estimate in a reference's header; NaN when absent or not a number ("nan" for 1 spp).
double read_own_error(const std::string& exr) {
  for (const auto& [k, v] : read_exr_metadata(exr)) {
    if (k != kOwnErrorKey) continue;
    char* end = nullptr;
    const double e = std::strtod(v.c_str(), &end);
    if (end != v.c_str() && *end == '\0') return e;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

bool sequence_moves(const Scene& scene, const Options& o) {
  return o.render.frames > 1 && (camera_of(scene, o).keys.size() > 1 || scene_animated(scene));
}

CameraKey camera_at(const Scene& scene, const Options& o, int frame) {
  return camera_of(scene, o).at_frame(frame, o.render.frames);
}

ReferenceCache::ReferenceCache(std::string dir) : dir_(std::move(dir)) {}

std::string ReferenceCache::path(const std::string& key) const { return (fs::path(dir_) / (key + ".exr")).string(); }

bool ReferenceCache::on_disk(const std::string& key) const { return fs::exists(path(key)); }

ReferenceJob ReferenceCache::describe(const Study& s, const Scene& scene, const std::string& scene_as_written,
                                      const std::string& scene_file_text, const Options& scene_defaults,
                                      const Options& o, int frame) const {
  ReferenceJob j;
  Options r = reference_options(scene_defaults, o);
  set_option(r, "render.spp", std::to_string(s.reference.spp));
  set_option(r, "render.seed", std::to_string(s.reference.seed));
  set_option(r, "render.frames", "1");
  for (const auto& [k, v] : s.reference.options) set_option(r, k, v);
  r.render.camera_path.clear();
  r.render.threads = 0;
  r.output = OutputOptions{};  // the display transform is not part of the reference
  j.options = r;
  j.camera = camera_at(scene, o, frame);
  std::string text = non_default_options(r) + scene_as_written + "\n" + scene_file_text + "\nhalves 2\ncamera";
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) text += fmt::format(" {:.6g}", j.camera.camera_from_world.m[a][b]);
  text += fmt::format(" fov {:.6g}", j.camera.fov_degrees);
  if (scene_animated(scene)) {  // the scene as it is at that frame
    j.frame = frame;
    // Keyed by the animated state, not the frame number: frames that look alike (a looping
    // animation, a light that is back on) share one reference.
    text += " animation state";
    for (const Animation& a : scene.animations) {
      const Mat4 m = a.transform(frame);
      for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) text += fmt::format(" {:.9g}", m.m[r][c]);
      text += fmt::format(" i {:.9g}", a.intensity(frame));
    }
  }
  j.key = hash_hex(text);
  return j;
}

const Image& ReferenceCache::get(const ReferenceJob& job, const Scene& scene) {
  std::lock_guard lock(mutex_);
  auto it = images_.find(job.key);
  if (it != images_.end()) return it->second;
  fs::create_directories(dir_);
  const std::string p = path(job.key);
  // Shards of a study (other processes, other machines) share references/: whoever needs a
  // reference first renders it while holding its lock; the others wait, then read the file.
  // The lock files live beside references/ (OUT/locks), so references/ holds only images.
  const fs::path locks = fs::path(dir_).parent_path() / "locks";
  fs::create_directories(locks);
  FileLock lock_file((locks / (job.key + ".lock")).string());
  if (fs::exists(p)) {
    ++reused_;
    errors_[job.key] = read_own_error(p);
    return images_[job.key] = read_image(p);
  }
  Scene moved = scene_animated(scene) ? scene_at_frame(scene, job.frame) : scene;  // the frame, static
  moved.camera.keys = {job.camera};
  Halves halves = render_halves(moved, job.options);
  // The estimate travels in the image's own header: written with it, atomically.
  write_exr(p, halves.mean,
            {{"restir.version", build_id()},
             {"restir.config", options_to_json(job.options, -1)},
             {"restir.reference", "1"},
             {kHalvesKey, fmt::format("{} {}", halves.spp[0], halves.spp[1])},
             {kOwnErrorKey, fmt::format("{:.17g}", halves.own_error)}});
  ++rendered_;
  errors_[job.key] = halves.own_error;
  return images_[job.key] = std::move(halves.mean);
}

double ReferenceCache::own_error(const std::string& key) const {
  std::lock_guard lock(mutex_);
  auto it = errors_.find(key);
  return it == errors_.end() ? std::numeric_limits<double>::quiet_NaN() : it->second;
}

}  // namespace rl::study
