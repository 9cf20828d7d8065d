// Pixel masks for metrics over part of a frame.
#pragma once
#include <cstdint>
#include <vector>

#include "frame/options.h"
#include "scene/scene.h"

namespace rl::study {

// The "reflective" pixels of a frame (the reflections study, issue 12): those whose primary
// surface, seen through the pixel centre with `camera` at o's film size, has roughness
// (bsdf_roughness: sqrt(alpha_x alpha_y), diffuse 1, smooth 0) at most max_roughness.
std::vector<uint8_t> reflective_mask(const Scene& scene, const Options& o, const CameraKey& camera, float max_roughness);

// The roughness bound of the *_reflective metrics: the ssr integrator's default cutoff.
inline constexpr float kReflectiveRoughness = 0.3f;

}  // namespace rl::study
