// The metrics of one study run, computed frame by frame as the renderer produces them (runner.cpp
// drives it): the rows of an over-time study, or the one row of the last frame.
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "frame/options.h"
#include "frame/stage_times.h"
#include "image/image.h"
#include "scene/scene.h"
#include "study/results.h"
#include "study/study_file.h"

namespace rl::study {

// Who a run is: the columns every row of it shares.
struct RunIdentity {
  std::string id, config, scene;  // scene: the path as written in the study
  uint64_t seed = 0;
};

// The q-quantile of v, linearly interpolated; kNone when v is empty.
double percentile(std::vector<double> v, double q);

class RunScorer {
 public:
  // references: (image, its own relMSE) -- one for a static camera, one per frame otherwise; none
  // when the study needs no reference.
  RunScorer(const Study& s, const Options& o, const Scene& scene, RunIdentity who,
            std::vector<std::pair<const Image*, double>> references);
  // Frame f's reference (null without one).
  const Image* ref_of(int frame) const;
  // Frame f, in order, as scored (the raw frame, or the denoiser's output), and its wall time.
  void frame(int f, const Image& img, double ms);
  // A study not over time: its one row, for the last frame scored and every frame's wall time.
  void last_frame(const Image& img, const std::vector<double>& frame_ms);
  // The metric "cost", after the rows: each frame's rays per pixel by kind (stage_times.h; a
  // per-frame row gets its frame's, the one row the medians over the frames) and the integrator's
  // buffers per pixel after the last frame (Integrator::buffer_bytes).
  void cost(const std::vector<StageTimes>& frames, size_t buffer_bytes);

  std::vector<Row> rows;

 private:
  size_t ref_slot(int frame) const { return refs_.size() == 1 ? size_t(0) : size_t(frame); }
  Row base_row(int frame) const;
  void image_metrics(Row& row, const Image& img, const Image& ref, bool last) const;

  const Study& s_;
  const Options& o_;
  RunIdentity who_;
  std::vector<std::pair<const Image*, double>> refs_;
  std::vector<std::pair<std::string, std::string>> values_;
  bool per_frame_;
  int frames_, flicker_from_;
  std::vector<uint8_t> reflective_;  // pixels of glossy/specular primary surfaces, at the last frame's camera
  std::vector<double> flicker_;
  Image running_, previous_;
};

}  // namespace rl::study
