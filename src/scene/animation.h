// Keyframed rigid motion and light intensity over the frames of a sequence (issue 11): the
// project's small extension of the pbrt-v4 subset. Inside an AttributeBegin block,
//   Attribute "shape" "string animation" "door.json"   animates the shapes that follow,
//   Attribute "light" "string animation" "blink.json"  animates the point / spot / distant / infinite lights,
// (pbrt-v4's own syntax for parameter defaults, so pbrt-v4 reads such a file and ignores the key).
// An animation file:
//   {"pivot": [x, y, z],                         rotation centre in world space (default origin)
//    "interpolation": "linear" | "step",         step: hold each key until the next (switches)
//    "repeat": N,                                optional: the keys repeat every N frames (a loop)
//    "keys": [{"frame": 0, "translate": [x, y, z], "rotate": [degrees, ax, ay, az], "intensity": 1},
//             ...]}
// Keys are at frames of the sequence, in increasing order; before the first key the first holds,
// after the last the last. With "repeat", frame f is read as f mod N, and keys lie in [0, N]. Between keys translation is interpolated linearly and rotation by
// slerp of unit quaternions (Shoemake 1985), intensity linearly. A key's transform is applied to
// the rest pose written in the scene: x -> translate + pivot + R (x - pivot). Intensity scales the
// emission of animated emissive shapes and lights (0 = off).
#pragma once
#include <string>
#include <vector>

#include "core/math.h"

namespace rl {

struct Scene;

struct AnimationKey {
  int frame = 0;
  Vec3 translate{0};
  float angle_degrees = 0;
  Vec3 axis{0, 1, 0};
  float intensity = 1;
};

struct Animation {
  std::string file;                 // where it was read from, for messages
  Vec3 pivot{0};
  bool step = false;                // "interpolation": "step"
  int repeat = 0;                   // "repeat": period in frames (0 = play once)
  std::vector<AnimationKey> keys;   // at least one, frames strictly increasing

  // World transform (applied to the rest pose) and intensity at frame f.
  Mat4 transform(int frame) const;
  float intensity(int frame) const;
};

// Reads an animation file. Throws SceneError naming the file and the offending key.
Animation load_animation(const std::string& path);

// True when anything in the scene is animated (shapes, lights).
bool scene_animated(const Scene& rest);
// True when an emitter moves or changes: an animated emissive shape, point, spot or distant light, or environment.
bool lights_animated(const Scene& rest);

// The scene at frame f of the sequence: `out` becomes `rest` with every animated shape and light
// moved and scaled. Static parts are copied unchanged, so frame f of a static scene equals rest.
void animate_scene(const Scene& rest, int frame, Scene& out);

// The scene at frame f as a static scene (nothing animated): e.g. for a per-frame reference.
Scene scene_at_frame(const Scene& rest, int frame);

}  // namespace rl
