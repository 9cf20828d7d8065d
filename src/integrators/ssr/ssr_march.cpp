#include "integrators/ssr/ssr_march.h"

namespace rl {

HiZLayout hiz_layout(int width, int height) {
  HiZLayout l;
  int w = width, h = height;
  for (;;) {
    l.width[l.levels] = w, l.height[l.levels] = h, l.offset[l.levels] = l.total;
    l.total += size_t(w) * size_t(h);
    ++l.levels;
    if ((w <= 1 && h <= 1) || l.levels == kMaxHiZLevels) break;
    w = (w + 1) / 2, h = (h + 1) / 2;
  }
  return l;
}

void HiZPyramid::build(const PerspectiveCamera& camera, const GBuffer& g) {
  layout = hiz_layout(g.width, g.height);
  z.assign(layout.total, ssr_detail::kInf);
  for (size_t i = 0; i < g.pixels.size(); ++i) z[i] = hiz_depth(g.pixels[i], camera.position(), camera.forward());
  const HiZView v = view();
  for (int l = 1; l < layout.levels; ++l)
    for (int y = 0; y < layout.height[l]; ++y)
      for (int x = 0; x < layout.width[l]; ++x) z[layout.offset[l] + size_t(y) * size_t(layout.width[l]) + size_t(x)] = hiz_reduce(v, l, x, y);
}

}  // namespace rl
