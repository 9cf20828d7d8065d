// The analytic scene of the AOV and denoiser tests (tests/frame/test_aov.cpp, tests/post/):
// a pinhole camera at the origin looking down +z (fov 60 on the 48-pixel axis), a diffuse card at
// z = 3 covering x < 0 (the left half of the image), a diffuse background plane at z = 10 and a
// two-sided 4 x 4 area light at z = -0.5 behind the camera, at x in [0.5, 4.5]: the card casts no
// shadow on the background at x > 0, so the lighting is smooth on each side of the card's edge. Every surface faces the camera
// (normal (0, 0, -1)); the card's edge is a sharp occlusion edge in the middle column.
#pragma once
#include <cmath>
#include <fstream>
#include <string>

#include "core/math.h"
#include "scene/loader.h"
#include "test_helpers.h"

namespace rl::test {

inline constexpr int kCardWidth = 64, kCardHeight = 48;
inline constexpr float kCardZ = 3, kBackgroundZ = 10, kCardFov = 60;

// blink: a second, brighter light (left of the camera) that is on for frames 0-5 and off from
// frame 6 (a step animation), for the temporal-gradient tests of A-SVGF; off: that light absent
// (the blinking scene's state from frame 6 on, for its reference).
enum class CardLight { steady, blink, off };
inline Scene card_scene(CardLight extra = CardLight::steady) {
  const auto dir = fresh_temp_dir("card-scene");
  const std::string path = (dir / "card.pbrt").string();
  std::string blink;
  if (extra == CardLight::blink) {
    std::ofstream(dir / "blink.json") << R"({"interpolation": "step", "keys": [{"frame": 0, "intensity": 1}, {"frame": 6, "intensity": 0}]})";
    blink = R"(AttributeBegin
  Attribute "shape" "string animation" "blink.json"
  AreaLightSource "diffuse" "rgb L" [12 12 12] "bool twosided" true
  Shape "trianglemesh" "point3 P" [-4.5 -2 -0.5  -0.5 -2 -0.5  -0.5 2 -0.5  -4.5 2 -0.5] "integer indices" [0 1 2 0 2 3]
AttributeEnd
)";
  }
  std::ofstream(path) << R"(LookAt 0 0 0  0 0 1  0 1 0
Camera "perspective" "float fov" 60
Film "rgb" "integer xresolution" 64 "integer yresolution" 48
WorldBegin
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [3 3 3] "bool twosided" true
  Shape "trianglemesh" "point3 P" [0.5 -2 -0.5  4.5 -2 -0.5  4.5 2 -0.5  0.5 2 -0.5] "integer indices" [0 1 2 0 2 3]
AttributeEnd
)" + blink + R"(Material "diffuse" "rgb reflectance" [0.6 0.5 0.4]
Shape "trianglemesh" "point3 P" [-20 -20 3  0 -20 3  0 20 3  -20 20 3] "integer indices" [0 1 2 0 2 3]
Material "diffuse" "rgb reflectance" [0.3 0.5 0.7]
Shape "trianglemesh" "point3 P" [-100 -100 10  100 -100 10  100 100 10  -100 100 10] "integer indices" [0 1 2 0 2 3]
)";
  return load_scene(path);
}

// The camera of the card scene moved by dx along x.
inline CameraKey card_camera(float dx) {
  CameraKey k;
  k.fov_degrees = kCardFov;
  look_at(Vec3(dx, 0, 0), Vec3(dx, 0, 1), Vec3(0, 1, 0), k.camera_from_world);
  return k;
}

// Raster shift (previous minus current, pixels) of a point at depth z when the camera moved by dx
// along its x axis: dx / (z tan(fov / 2)) in screen units, height / 2 pixels per unit (fov spans y).
inline float card_shift(float dx, float z) {
  return dx / (z * std::tan(kCardFov * 0.5f * kPi / 180.0f)) * 0.5f * float(kCardHeight);
}

}  // namespace rl::test
