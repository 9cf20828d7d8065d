#include "viewer/display.h"

#include <algorithm>
#include <cmath>

#include "core/parallel.h"
#include "image/tonemap.h"
#include "frame/render.h"

namespace rl::viewer {

void Accumulation::add(const Image& frame) {
  if (count_ == 0 || mean_.width != frame.width || mean_.height != frame.height) {
    mean_ = frame;
    count_ = 0;
  }
  ++count_;
  if (count_ > 1) accumulate_mean(mean_, frame, count_);
  last_ = frame;
}

namespace {

Rgb false_colour(double e) {
  // log10 of the error from -4 (black) to 0 (red) through blue, green, yellow.
  static const Rgb stops[] = {Rgb(0, 0, 0), Rgb(0, 0, 1), Rgb(0, 1, 0), Rgb(1, 1, 0), Rgb(1, 0, 0)};
  if (!(e > 1e-4)) return stops[0];
  const double t = std::clamp(std::log10(e) + 4.0, 0.0, 4.0);
  const int i = std::min(int(t), 3);
  const float f = float(t - i);
  return stops[i] * (1 - f) + stops[i + 1] * f;
}

void tonemap_rows(const Image& hdr, const OutputOptions& o, Image& out, int x0, int x1) {
  parallel_for(hdr.height, [&](int y) {
    for (int x = x0; x < x1; ++x) out.at(x, y) = tonemap_pixel(hdr.at(x, y), o);
  });
}

}  // namespace

Image error_map(const Image& test, const Image& reference) {
  Image out(test.width, test.height);
  parallel_for(test.height, [&](int y) {
    for (int x = 0; x < test.width; ++x) {
      const Rgb t = test.at(x, y), r = reference.at(x, y);
      double e = 0;
      for (int c = 0; c < 3; ++c) {
        const double d = double(t[c]) - double(r[c]), den = double(r[c]) + 0.01;
        e += den != 0 ? d * d / (den * den) : 0;
      }
      out.at(x, y) = false_colour(e / 3);
    }
  });
  return out;
}

Image compose_view(ViewMode mode, const Image& hdr, const Image* reference, const OutputOptions& o, float split) {
  const bool have_ref = reference && reference->width == hdr.width && reference->height == hdr.height;
  if (have_ref && mode == ViewMode::error) return error_map(hdr, *reference);
  Image out(hdr.width, hdr.height);
  if (have_ref && mode == ViewMode::split) {
    const int cut = std::clamp(int(std::lround(double(split) * hdr.width)), 0, hdr.width);
    tonemap_rows(hdr, o, out, 0, cut);
    tonemap_rows(*reference, o, out, cut, hdr.width);
  } else {
    tonemap_rows(hdr, o, out, 0, hdr.width);
  }
  return out;
}

Image downsample(const Image& img, int factor) {
  if (factor <= 1) return img;
  Image out(std::max(1, img.width / factor), std::max(1, img.height / factor));
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      Rgb s(0);
      int n = 0;
      for (int j = y * factor; j < std::min(img.height, (y + 1) * factor); ++j)
        for (int i = x * factor; i < std::min(img.width, (x + 1) * factor); ++i, ++n) s += img.at(i, j);
      out.at(x, y) = s / float(std::max(n, 1));
    }
  return out;
}

const char* view_name(ViewMode m) {
  switch (m) {
    case ViewMode::radiance: return "radiance";
    case ViewMode::error: return "error";
    case ViewMode::split: return "split";
  }
  return "?";
}

void FrameHistory::add(double ms) {
  if (ms_.size() < capacity_) {
    ms_.push_back(ms);
    return;
  }
  ms_[next_] = ms;
  next_ = (next_ + 1) % capacity_;
}

std::vector<float> FrameHistory::values() const {
  std::vector<float> v;
  v.reserve(ms_.size());
  for (size_t i = 0; i < ms_.size(); ++i) v.push_back(float(ms_[(next_ + i) % ms_.size()]));
  return v;
}

double FrameHistory::mean_ms(size_t n) const {
  const std::vector<float> v = values();
  n = std::min(n, v.size());
  if (n == 0) return 0;
  double s = 0;
  for (size_t i = v.size() - n; i < v.size(); ++i) s += v[i];
  return s / double(n);
}

bool DrawPacer::due(double now, bool input, bool frame_waiting) const {
  if (input || settle_ > 0 || now - last_ >= 1.0) return true;
  return frame_waiting && now - last_ >= interval();
}

double DrawPacer::wait_s(double now, bool frame_waiting) const {
  if (settle_ > 0) return 1.0 / 60;
  double t = last_ + 1.0 - now;
  if (frame_waiting) t = std::min(t, last_ + interval() - now);
  return std::clamp(t, 0.0, 1.0);
}

void DrawPacer::drawn(double now, double cost_s, bool input) {
  // The first redraw sets the mean; then a slow average, so one stall does not stop the display.
  cost_ = cost_ == 0 ? cost_s : 0.8 * cost_ + 0.2 * cost_s;
  last_ = now;
  settle_ = input ? 3 : std::max(0, settle_ - 1);
}

}  // namespace rl::viewer
