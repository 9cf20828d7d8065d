// What the viewer shows, computed from the rendered frames: the progressive mean (or the raw
// frame), the display transform, the error map against a reference and the A/B split. Pure
// functions over images, unit-tested without a display.
#pragma once
#include <cstddef>
#include <vector>

#include "image/image.h"
#include "image/tonemap_options.h"

namespace rl::viewer {

enum class ViewMode { radiance, error, split };

// Frames since the last reset, and their mean (the progressive image) or the last frame alone.
class Accumulation {
 public:
  void reset() { count_ = 0; }
  // Adds a frame; a frame of another size restarts the mean.
  void add(const Image& frame);
  int count() const { return count_; }
  const Image& mean() const { return mean_; }
  const Image& last() const { return last_; }
  // What the viewer shows and saves: the mean when accumulating, else the last frame.
  const Image& shown(bool accumulate) const { return accumulate ? mean_ : last_; }

 private:
  Image mean_, last_;
  int count_ = 0;
};

// Per-pixel relative squared error (t - r)^2 / (r + 0.01)^2 (pbrt's relMSE terms, as
// image/metrics.h), averaged over the channels and mapped to a false colour: black = 0, then
// blue, green, yellow, red at 10^-3, 10^-2, 10^-1, 1 and beyond. Same-size images.
Image error_map(const Image& test, const Image& reference);

// The LDR (display-ready, [0,1], sRGB when o.srgb) image of a view: radiance = tonemap(hdr);
// error = error_map(hdr, reference); split = tonemap(hdr) left of column split x width and
// tonemap(reference) right of it. Without a reference (null or another size) every view is the
// radiance view. The tone mapping runs over rows in parallel: it runs on every displayed frame.
Image compose_view(ViewMode mode, const Image& hdr, const Image* reference, const OutputOptions& o, float split);

// Box filter over factor x factor pixel blocks (the size is rounded down; at least 1x1).
Image downsample(const Image& img, int factor);

// What the viewer shows besides the options: the view, the A/B split and accumulation.
struct ViewState {
  ViewMode mode = ViewMode::radiance;
  float split = 0.5f;       // split view: the render left of split x width, the reference right of it
  bool accumulate = true;   // show the progressive mean, or each frame's raw output
};
const char* view_name(ViewMode m);

// The last `capacity` frame times, for the plot and the ms / fps readouts.
class FrameHistory {
 public:
  explicit FrameHistory(size_t capacity = 300) : capacity_(capacity) {}
  void add(double ms);
  void clear() { ms_.clear(); next_ = 0; }
  // Oldest first.
  std::vector<float> values() const;
  size_t size() const { return ms_.size(); }
  // Mean of the last n values (all when fewer); 0 when empty.
  double mean_ms(size_t n = 30) const;
  double fps(size_t n = 30) const { return mean_ms(n) > 0 ? 1000.0 / mean_ms(n) : 0; }

 private:
  size_t capacity_;
  std::vector<double> ms_;  // ring buffer once full: next_ is the oldest
  size_t next_ = 0;
};

// When the window redraws. A redraw takes CPU from the renderer (with software OpenGL 8-20 ms per
// redraw on the machines this was measured on; under 1 ms with a GPU driver), so while nothing
// moves the window spends at most `budget` of the wall time drawing: a new frame is drawn once
// the time since the last redraw is at least the redraw's cost over the budget. Input draws at
// once and for a few redraws after (the panel shows a click's effect a frame later), and the
// window redraws at least once a second. The renderer renders every frame either way; fewer of
// them are shown when redraws are expensive.
class DrawPacer {
 public:
  explicit DrawPacer(double budget = 0.03) { set_budget(budget); }
  void set_budget(double b) { budget_ = b < 1e-3 ? 1e-3 : b > 1 ? 1 : b; }
  double budget() const { return budget_; }
  // Whether to redraw now (s: a steady clock in seconds).
  bool due(double now, bool input, bool frame_waiting) const;
  // Seconds the window may sleep before it has to look again (a waiting frame, the settle
  // redraws, the once-a-second redraw).
  double wait_s(double now, bool frame_waiting) const;
  // After a redraw that took cost_s seconds.
  void drawn(double now, double cost_s, bool input);
  double cost_s() const { return cost_; }

 private:
  double interval() const { return cost_ / budget_; }
  double budget_ = 0.03;
  double cost_ = 0;          // exponential mean of the redraw cost (s)
  double last_ = -1e9;       // when the window was last drawn
  int settle_ = 0;           // redraws still to make after input
};

}  // namespace rl::viewer
