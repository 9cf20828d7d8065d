// A linear-RGB float image. The one image type of the project (film, textures, env maps, metrics).
#pragma once
#include <cstddef>
#include <vector>

#include "core/math.h"

namespace rl {

struct Image {
  int width = 0, height = 0;
  std::vector<Rgb> pixels;  // row-major, row 0 at the top

  Image() = default;
  Image(int w, int h, Rgb fill = Rgb(0)) : width(w), height(h), pixels(size_t(w) * size_t(h), fill) {}
  Rgb& at(int x, int y) { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
  const Rgb& at(int x, int y) const { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
  size_t size() const { return pixels.size(); }
  bool empty() const { return pixels.empty(); }
};

}  // namespace rl
