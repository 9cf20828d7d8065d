#include "scene/texture.h"

namespace rl {

namespace {
const Rgb& texel(const Image& img, int x, int y) {
  // Repeat wrapping.
  x %= img.width;
  y %= img.height;
  if (x < 0) x += img.width;
  if (y < 0) y += img.height;
  return img.at(x, y);
}
}  // namespace

Rgb eval_texture(const Texture& tex, Vec2 uv) {
  float u = uv.x * tex.uscale + tex.udelta, v = uv.y * tex.vscale + tex.vdelta;
  switch (tex.kind) {
    case Texture::Kind::constant:
      return tex.value;
    case Texture::Kind::checkerboard: {
      int cu = int(std::floor(u)), cv = int(std::floor(v));
      return ((cu + cv) & 1) == 0 ? tex.tex1 : tex.tex2;
    }
    case Texture::Kind::image: {
      const Image& img = tex.image;
      if (img.empty()) return tex.value;
      // Bilinear filtering on texel centres; image row 0 is the top (v = 1).
      float x = u * float(img.width) - 0.5f, y = (1 - v) * float(img.height) - 0.5f;
      float fx = std::floor(x), fy = std::floor(y);
      int x0 = int(fx), y0 = int(fy);
      float dx = x - fx, dy = y - fy;
      return (1 - dx) * (1 - dy) * texel(img, x0, y0) + dx * (1 - dy) * texel(img, x0 + 1, y0) +
             (1 - dx) * dy * texel(img, x0, y0 + 1) + dx * dy * texel(img, x0 + 1, y0 + 1);
    }
  }
  return tex.value;
}

}  // namespace rl
