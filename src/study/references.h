// Converged references for a study, rendered by the path tracer once and cached on disk as
// DIR/references/<hash>.exr, where the hash covers the reference's full option set, the scene
// path, the scene file's contents and the camera of the frame. A later run (or another study
// writing into the same DIR) reuses the file.
//
// The reference of a configuration: integrator pt, the configuration's film (size, filter) and
// path.max_depth (restir-di: path.max_depth = 1, direct light only; the others: their own path.*),
// reference.spp samples,
// reference.seed, one frame rendered with the camera of the frame being compared; every other
// option at its default (scene hints applied), then the study's reference.options.
//
// A reference is rendered as two independent halves (reference.seed and a second seed, ⌈N/2⌉ and
// ⌊N/2⌋ spp) and saved as their spp-weighted mean, so that its own error can be estimated at no
// extra cost: for independent unbiased halves A, B with per-pixel variances σ²/n_A, σ²/n_B,
// E[(A − B)²] = σ²(1/n_A + 1/n_B) and the mean's variance is σ²/N = E[(A − B)²] n_A n_B / N².
// own_error() is that estimate in relMSE (eps 0.01, the mean as denominator, as rel_mse), kept in
// the image's EXR header (restir.reference_relmse). The relMSE of a configuration against a noisy
// reference is its own relMSE plus the reference's, in expectation, so this tells whether a
// reference is converged enough for the differences a study reports (docs/results asks for below
// 10% of the smallest one).
#pragma once
#include <map>
#include <mutex>
#include <string>

#include "image/image.h"
#include "frame/options.h"
#include "scene/scene.h"
#include "study/study_file.h"

namespace rl::study {

struct ReferenceJob {
  std::string key;        // content hash = file stem
  Options options;        // what pt renders
  CameraKey camera;       // the frame's camera
  int frame = 0;          // the frame of an animated scene (scene_at_frame)
};

class ReferenceCache {
 public:
  explicit ReferenceCache(std::string dir);
  // What the reference for frame `frame` of a configuration is (no rendering).
  ReferenceJob describe(const Study& s, const Scene& scene, const std::string& scene_as_written,
                        const std::string& scene_file_text, const Options& scene_defaults, const Options& o,
                        int frame) const;
  bool on_disk(const std::string& key) const;
  // Loads the cached file, or renders and writes it. Thread-safe; renders each key once.
  const Image& get(const ReferenceJob& job, const Scene& scene);
  std::string path(const std::string& key) const;
  // The estimated relMSE of a loaded reference against the converged image (above); NaN when
  // unknown (a 1-spp reference, or a file without its estimate).
  double own_error(const std::string& key) const;
  int rendered() const { return rendered_; }
  int reused() const { return reused_; }

 private:
  std::string dir_;
  std::map<std::string, Image> images_;
  std::map<std::string, double> errors_;
  mutable std::mutex mutex_;
  int rendered_ = 0, reused_ = 0;
};

// True when the camera moves across the frames of o (camera path or animated scene camera).
bool sequence_moves(const Scene& scene, const Options& o);
// The camera of frame f of o (camera path applied).
CameraKey camera_at(const Scene& scene, const Options& o, int frame);

}  // namespace rl::study
