// Where a frame's time goes: wall time per stage (primary hits, candidates, temporal reuse,
// spatial reuse, shading, ...). Integrators time their stages with StageTimer; the render driver
// returns them per frame (RenderResult::frame_stages), `restir render --timings` writes them as
// CSV columns and the benchmarks print them. Part of what a study measures (issue 9).
#pragma once
#include <chrono>
#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

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
};

// Adds the wall time of its scope to `times` (which may be null: nothing is recorded).
class StageTimer {
 public:
  StageTimer(StageTimes* times, std::string_view stage) : times_(times), stage_(stage), start_(std::chrono::steady_clock::now()) {}
  ~StageTimer() {
    if (times_) times_->add(stage_, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count());
  }
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;

 private:
  StageTimes* times_;
  std::string_view stage_;
  std::chrono::steady_clock::time_point start_;
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

}  // namespace rl
