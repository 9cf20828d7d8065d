#pragma once
#include "scene/scene.h"

namespace rl {
// Texture value at uv: bilinear lookup with repeat wrapping for images
// (v = 0 at the image's bottom row, as pbrt), checkerboard in uv cells.
Rgb eval_texture(const Texture& tex, Vec2 uv);
// A material's reflectance at a hit: its texture if it has one, else its constant.
inline Rgb material_reflectance(const Scene& scene, const Material& m, Vec2 uv) {
  return m.reflectance_texture >= 0 ? eval_texture(scene.textures[size_t(m.reflectance_texture)], uv) : m.reflectance;
}
}  // namespace rl
