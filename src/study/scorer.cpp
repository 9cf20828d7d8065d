// A study run's metrics, frame by frame (scorer.h).
#include "study/scorer.h"

#include <algorithm>
#include <numeric>
#include <optional>

#include "image/metrics.h"
#include "study/images.h"
#include "study/masks.h"
#include "study/references.h"

namespace rl::study {

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return kNone;
  std::sort(v.begin(), v.end());
  double pos = q * double(v.size() - 1);
  size_t i = size_t(pos);
  double f = pos - double(i);
  return i + 1 < v.size() ? v[i] * (1 - f) + v[i + 1] * f : v[i];
}

RunScorer::RunScorer(const Study& s, const Options& o, const Scene& scene, RunIdentity who,
                     std::vector<std::pair<const Image*, double>> references)
    : s_(s), o_(o), who_(std::move(who)), refs_(std::move(references)), values_(option_values(o)),
      per_frame_(s.per_frame()), frames_(o.render.frames),
      // flicker: FLIP between consecutive frames (temporal instability under a still camera), per
      // frame in over-time studies, else the mean over the second half of the sequence (past the
      // warm-up of temporal reuse and of the denoiser's history).
      flicker_from_(per_frame_ ? 1 : std::max(1, frames_ / 2)) {
  if (s.has_metric("relmse_reflective") || s.has_metric("flip_reflective"))
    reflective_ = reflective_mask(scene, o, camera_at(scene, o, frames_ - 1), kReflectiveRoughness);
}

const Image* RunScorer::ref_of(int frame) const { return refs_.empty() ? nullptr : refs_[ref_slot(frame)].first; }

Row RunScorer::base_row(int frame) const {
  Row r;
  r.id = who_.id;
  r.config = who_.config;
  r.scene = who_.scene;
  r.seed = who_.seed;
  r.frame = frame;
  r.options = values_;
  return r;
}

void RunScorer::image_metrics(Row& row, const Image& img, const Image& ref, bool last) const {
  if (s_.has_metric("mse")) row.metrics["mse"] = mse(img, ref);
  if (s_.has_metric("relmse")) {
    row.metrics["relmse"] = rel_mse(img, ref);
    row.metrics["ref_relmse"] = refs_[ref_slot(row.frame)].second;  // the reference's own relMSE
  }
  if (s_.has_metric("relmse_lowpass")) row.metrics["relmse_lowpass"] = rel_mse_lowpass(img, ref);
  if (!last) return;
  if (s_.has_metric("flip")) row.metrics["flip"] = flip_metric(img, ref, o_.output);
  if (s_.has_metric("relmse_reflective")) row.metrics["relmse_reflective"] = rel_mse(img, ref, &reflective_);
  if (s_.has_metric("flip_reflective")) row.metrics["flip_reflective"] = flip_metric(img, ref, o_.output, reflective_);
}

void RunScorer::frame(int f, const Image& img, double ms) {
  const bool flicker = s_.has_metric("flicker");
  std::optional<double> flick;
  if (flicker && f >= flicker_from_) flicker_.push_back(*(flick = flip_metric(img, previous_, o_.output)));
  if (flicker && f + 1 < frames_) previous_ = img;
  if (!per_frame_) return;
  if (running_.empty()) running_ = Image(img.width, img.height);
  const float w = 1.0f / float(f + 1);
  for (size_t i = 0; i < img.size(); ++i) running_.pixels[i] += (img.pixels[i] - running_.pixels[i]) * w;
  Row row = base_row(f);
  row.metrics["ms_median"] = ms;
  row.metrics["ms_iqr"] = 0;
  row.metrics["fps"] = 1000.0 / ms;
  if (flick) row.metrics["flicker"] = *flick;
  if (const Image* ref = ref_of(f)) {
    image_metrics(row, img, *ref, f + 1 == frames_);
    // Convergence of the running mean: meaningful for a static camera only.
    if (refs_.size() == 1) row.metrics["convergence"] = rel_mse(running_, *ref);
  }
  rows.push_back(std::move(row));
}

void RunScorer::last_frame(const Image& img, const std::vector<double>& frame_ms) {
  if (per_frame_) return;
  Row row = base_row(frames_ - 1);
  const double med = percentile(frame_ms, 0.5);
  row.metrics["ms_median"] = med;
  row.metrics["ms_iqr"] = percentile(frame_ms, 0.75) - percentile(frame_ms, 0.25);
  row.metrics["fps"] = 1000.0 / med;
  if (!flicker_.empty())
    row.metrics["flicker"] = std::accumulate(flicker_.begin(), flicker_.end(), 0.0) / double(flicker_.size());
  if (const Image* ref = ref_of(frames_ - 1)) image_metrics(row, img, *ref, true);
  rows.push_back(std::move(row));
}

void RunScorer::cost(const std::vector<StageTimes>& frames, size_t buffer_bytes) {
  if (!s_.has_metric("cost")) return;
  const double pixels = double(o_.film.width) * double(o_.film.height);
  std::vector<double> closest, any;
  for (const StageTimes& st : frames) {
    closest.push_back(double(st.total_rays().closest) / pixels);
    any.push_back(double(st.total_rays().any) / pixels);
  }
  for (Row& row : rows) {
    const bool one = per_frame_ && row.frame >= 0 && size_t(row.frame) < frames.size();
    const double c = one ? closest[size_t(row.frame)] : percentile(closest, 0.5);
    const double a = one ? any[size_t(row.frame)] : percentile(any, 0.5);
    row.metrics["closest_px"] = c;
    row.metrics["any_px"] = a;
    row.metrics["rays_px"] = c + a;
    row.metrics["bytes_px"] = double(buffer_bytes) / pixels;
  }
}

}  // namespace rl::study
