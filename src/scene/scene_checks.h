// Validation of a loaded scene: every loader ends with it, so no non-finite or absurd value
// reaches Embree or an integrator, whatever the file format.
#pragma once
#include "scene/scene.h"

namespace rl {

// Throws SceneError naming where the bad value came from (the mesh's source "file:line", or the
// scene file) for: non-finite or huge (> kMaxWorldCoordinate) vertices, sphere centres and radii,
// point-light positions and the camera position; meshes without triangles; non-finite or
// negative emission and light intensities; material values outside their physical range
// (reflectance in [0, 1], eta > 0, k >= 0, roughness >= 0); non-finite texture or environment
// pixels; a singular camera transform.
void validate_scene(const Scene& scene);

// True if the scene has any emitter (area light with a positive radiance, point light with a
// positive intensity, environment light).
bool scene_has_lights(const Scene& scene);

// Prints "FILE: warning: the scene has no light source ..." to stderr when it has none.
void warn_if_no_lights(const Scene& scene);

}  // namespace rl
