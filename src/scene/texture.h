#pragma once
#include "scene/scene.h"
#include "scene/scene_view.h"

namespace rl {
// Texture value at uv (scene_view.h's eval_texture, on the texture's own image).
inline Rgb eval_texture(const Texture& tex, Vec2 uv) { return eval_texture(tex, image_view(tex.image), uv); }
// A material's reflectance at a hit: its texture if it has one, else its constant.
inline Rgb material_reflectance(const Scene& scene, const Material& m, Vec2 uv) {
  return m.reflectance_texture >= 0 ? eval_texture(scene.textures[size_t(m.reflectance_texture)], uv) : m.reflectance;
}
}  // namespace rl
