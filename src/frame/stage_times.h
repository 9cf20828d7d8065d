// Where a frame's time goes: wall time per stage (primary hits, candidates, temporal reuse,
// spatial reuse, shading, ...) and, while a frame counts them, the rays each stage traced
// (core/ray_counter.h). Integrators time their stages with StageTimer; the render driver returns
// them per frame (RenderResult::frame_stages), `restir render --timings` writes them as CSV columns
// and the benchmarks print them. Part of what a study measures (issue 9).
#pragma once
#include <chrono>
#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/ray_counter.h"

namespace rl {

struct StageTimes {
  // (stage, ms) in the order the stages first ran; the chains of render.spp add to one entry.
  std::vector<std::pair<std::string, double>> ms;

  void add(std::string_view stage, double value) {
    for (auto& [name, t] : ms)
      if (name == stage) {
        t += value;
        return;
      }
    ms.emplace_back(std::string(stage), value);
  }
  double total() const {
    double s = 0;
    for (const auto& e : ms) s += e.second;
    return s;
  }
  double of(std::string_view stage) const {
    for (const auto& [name, t] : ms)
      if (name == stage) return t;
    return 0;
  }

  // (stage, rays) of the stages that traced any, in the order they first did; like ms, the chains
  // of render.spp add to one entry.
  std::vector<std::pair<std::string, RayCounts>> rays;
  // The running totals of the rays the frame being rendered traced so far: set by the frame while
  // it renders (RayCountScope), read by every StageTimer at its start and end. Unset: not counted.
  std::function<RayCounts()> ray_totals;

  void add_rays(std::string_view stage, const RayCounts& c) {
    if (c.total() == 0) return;
    for (auto& [name, r] : rays)
      if (name == stage) {
        r += c;
        return;
      }
    rays.emplace_back(std::string(stage), c);
  }
  RayCounts rays_of(std::string_view stage) const {
    for (const auto& [name, r] : rays)
      if (name == stage) return r;
    return {};
  }
  RayCounts total_rays() const {
    RayCounts s;
    for (const auto& e : rays) s += e.second;
    return s;
  }
};

// Adds the wall time of its scope to `times` (which may be null: nothing is recorded) and, while
// the frame counts rays, the rays traced in it. The totals are read outside the timed interval.
class StageTimer {
 public:
  StageTimer(StageTimes* times, std::string_view stage) : times_(times), stage_(stage) {
    counting_ = times_ && times_->ray_totals;
    if (counting_) rays_ = times_->ray_totals();
    start_ = std::chrono::steady_clock::now();
  }
  ~StageTimer() {
    if (!times_) return;
    times_->add(stage_, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count());
    if (counting_ && times_->ray_totals) times_->add_rays(stage_, times_->ray_totals() - rays_);
  }
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;

 private:
  StageTimes* times_;
  std::string_view stage_;
  bool counting_ = false;
  RayCounts rays_;
  std::chrono::steady_clock::time_point start_;
};

// Counts the rays of a frame for its lifetime: `totals` (a backend world's ray_totals) becomes
// times' source of running totals, and is removed again at the end of the scope.
class RayCountScope {
 public:
  RayCountScope(StageTimes* times, std::function<RayCounts()> totals) : times_(times) {
    if (times_) times_->ray_totals = std::move(totals);
  }
  ~RayCountScope() {
    if (times_) times_->ray_totals = nullptr;
  }
  RayCountScope(const RayCountScope&) = delete;
  RayCountScope& operator=(const RayCountScope&) = delete;

 private:
  StageTimes* times_;
};

// The stage names in the order they first appear over all frames (frame 0 has no temporal stage).
// A stage first seen in a later frame goes right after the stage that precedes it there.
inline std::vector<std::string> stage_names(const std::vector<StageTimes>& frames) {
  std::vector<std::string> names;
  for (const StageTimes& f : frames) {
    size_t at = 0;  // insertion point: after the last stage of this frame already placed
    for (const auto& e : f.ms) {
      size_t i = 0;
      while (i < names.size() && names[i] != e.first) ++i;
      if (i == names.size()) names.insert(names.begin() + std::ptrdiff_t(at), e.first), i = at;
      at = i + 1;
    }
  }
  return names;
}

// The stages of stage_names(frames) that traced rays in any frame, in the same order.
inline std::vector<std::string> ray_stage_names(const std::vector<StageTimes>& frames) {
  std::vector<std::string> names;
  for (const std::string& n : stage_names(frames))
    for (const StageTimes& f : frames)
      if (f.rays_of(n).total() > 0) {
        names.push_back(n);
        break;
      }
  return names;
}

}  // namespace rl
