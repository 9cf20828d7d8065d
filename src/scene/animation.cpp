#include "scene/animation.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "scene/loader.h"
#include "scene/scene.h"

namespace rl {

namespace {

// Unit quaternion (w, v) for rotations: slerp between keys, then a matrix.
struct Quat {
  float w = 1;
  Vec3 v{0};
};

Quat from_axis_angle(float degrees, Vec3 axis) {
  const float half = 0.5f * degrees * kPi / 180.0f;
  return {std::cos(half), normalize(axis) * std::sin(half)};
}

// Shoemake 1985: the shortest arc between two unit quaternions at constant angular speed.
Quat slerp(Quat a, Quat b, float t) {
  float c = a.w * b.w + dot(a.v, b.v);
  if (c < 0) {  // q and -q are one rotation: take the short way
    b = {-b.w, -b.v};
    c = -c;
  }
  float ka = 1 - t, kb = t;
  if (c < 0.9995f) {
    const float theta = std::acos(std::min(c, 1.0f)), s = std::sin(theta);
    ka = std::sin((1 - t) * theta) / s;
    kb = std::sin(t * theta) / s;
  }
  Quat q{ka * a.w + kb * b.w, a.v * ka + b.v * kb};
  const float n = std::sqrt(q.w * q.w + dot(q.v, q.v));
  return {q.w / n, q.v / n};
}

Mat4 to_matrix(Quat q) {
  const float w = q.w, x = q.v.x, y = q.v.y, z = q.v.z;
  Mat4 m;
  m.m[0][0] = 1 - 2 * (y * y + z * z);
  m.m[0][1] = 2 * (x * y - w * z);
  m.m[0][2] = 2 * (x * z + w * y);
  m.m[1][0] = 2 * (x * y + w * z);
  m.m[1][1] = 1 - 2 * (x * x + z * z);
  m.m[1][2] = 2 * (y * z - w * x);
  m.m[2][0] = 2 * (x * z - w * y);
  m.m[2][1] = 2 * (y * z + w * x);
  m.m[2][2] = 1 - 2 * (x * x + y * y);
  return m;
}

// The pair of keys around frame f and the fraction between them (0 before the first key, 1 after
// the last, 0 between keys with step interpolation).
void bracket(const Animation& a, int frame, const AnimationKey*& k0, const AnimationKey*& k1, float& t) {
  k0 = k1 = &a.keys.front();
  t = 0;
  if (a.repeat > 0) frame = ((frame % a.repeat) + a.repeat) % a.repeat;  // a loop: the frame within its period
  if (frame <= a.keys.front().frame) return;
  k0 = k1 = &a.keys.back();
  if (frame >= a.keys.back().frame) return;
  for (size_t i = 0; i + 1 < a.keys.size(); ++i)
    if (frame < a.keys[i + 1].frame) {
      k0 = &a.keys[i];
      k1 = &a.keys[i + 1];
      t = a.step ? 0.0f : float(frame - k0->frame) / float(k1->frame - k0->frame);
      return;
    }
}

Vec3 json_vec3(const nlohmann::json& j, const std::string& where) {
  if (!j.is_array() || j.size() != 3) throw SceneError(where + " must be an array of 3 numbers");
  Vec3 v;
  float* c[3] = {&v.x, &v.y, &v.z};
  for (size_t i = 0; i < 3; ++i) {
    if (!j[i].is_number()) throw SceneError(where + " must hold numbers");
    const double d = j[i].get<double>();
    if (!(std::fabs(d) <= kMaxWorldCoordinate)) throw SceneError(where + " is beyond the supported world extent");
    *c[i] = float(d);
  }
  return v;
}

AnimationKey parse_key(const nlohmann::json& k, size_t index) {
  const std::string where = fmt::format("keys[{}]", index);
  if (!k.is_object()) throw SceneError(where + " must be an object");
  for (const auto& [name, value] : k.items())
    if (name != "frame" && name != "translate" && name != "rotate" && name != "intensity")
      throw SceneError(fmt::format("{}: unknown key \"{}\" (frame, translate, rotate, intensity)", where, name));
  AnimationKey key;
  if (!k.contains("frame") || !k["frame"].is_number_integer() || k["frame"].get<long long>() < 0 ||
      k["frame"].get<long long>() > 100000000)
    throw SceneError(where + ".frame must be an integer frame number in [0, 1e8]");
  key.frame = int(k["frame"].get<long long>());
  if (k.contains("translate")) key.translate = json_vec3(k["translate"], where + ".translate");
  if (k.contains("rotate")) {
    const auto& r = k["rotate"];
    if (!r.is_array() || r.size() != 4 || !std::all_of(r.begin(), r.end(), [](const auto& x) { return x.is_number(); }))
      throw SceneError(where + ".rotate must be [degrees, axis x, axis y, axis z]");
    double v[4];
    for (size_t i = 0; i < 4; ++i) {
      v[i] = r[i].get<double>();  // checked as a double: a float cast of 1e300 is undefined
      if (!(std::fabs(v[i]) <= 1e6)) throw SceneError(where + ".rotate: each number must lie in [-1e6, 1e6]");
    }
    key.angle_degrees = float(v[0]);
    key.axis = {float(v[1]), float(v[2]), float(v[3])};
    if (!(length(key.axis) > 1e-12f)) throw SceneError(where + ".rotate needs a non-zero axis");
  }
  if (k.contains("intensity")) {
    if (!k["intensity"].is_number() || !(k["intensity"].get<double>() >= 0) || !(k["intensity"].get<double>() <= 1e6))
      throw SceneError(where + ".intensity must be a number in [0, 1e6]");
    key.intensity = float(k["intensity"].get<double>());
  }
  return key;
}

}  // namespace

Mat4 Animation::transform(int frame) const {
  const AnimationKey *k0, *k1;
  float t;
  bracket(*this, frame, k0, k1, t);
  const Quat q = slerp(from_axis_angle(k0->angle_degrees, k0->axis), from_axis_angle(k1->angle_degrees, k1->axis), t);
  const Vec3 tr = k0->translate * (1 - t) + k1->translate * t;
  return translate(tr + pivot) * to_matrix(q) * translate(-pivot);
}

float Animation::intensity(int frame) const {
  const AnimationKey *k0, *k1;
  float t;
  bracket(*this, frame, k0, k1, t);
  return k0->intensity * (1 - t) + k1->intensity * t;
}

Animation load_animation(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw SceneError(path, 0, "cannot open animation file");
  std::stringstream ss;
  ss << in.rdbuf();
  Animation a;
  a.file = path;
  try {
    const nlohmann::json j = nlohmann::json::parse(ss.str());
    if (!j.is_object()) throw SceneError("must be a JSON object with \"keys\"");
    for (const auto& [name, value] : j.items())
      if (name != "pivot" && name != "interpolation" && name != "keys" && name != "repeat")
        throw SceneError(fmt::format("unknown key \"{}\" (pivot, interpolation, repeat, keys)", name));
    if (j.contains("pivot")) a.pivot = json_vec3(j["pivot"], "pivot");
    if (j.contains("interpolation")) {
      const std::string m = j["interpolation"].is_string() ? j["interpolation"].get<std::string>() : "";
      if (m != "linear" && m != "step") throw SceneError("\"interpolation\" must be \"linear\" or \"step\"");
      a.step = m == "step";
    }
    if (j.contains("repeat")) {
      if (!j["repeat"].is_number_integer() || j["repeat"].get<long long>() < 1 || j["repeat"].get<long long>() > 100000000)
        throw SceneError("\"repeat\" must be an integer period in frames in [1, 1e8]");
      a.repeat = int(j["repeat"].get<long long>());
    }
    if (!j.contains("keys") || !j["keys"].is_array() || j["keys"].empty())
      throw SceneError("\"keys\" must be a non-empty list");
    for (size_t i = 0; i < j["keys"].size(); ++i) {
      a.keys.push_back(parse_key(j["keys"][i], i));
      if (i > 0 && a.keys[i].frame <= a.keys[i - 1].frame)
        throw SceneError(fmt::format("keys[{}].frame {} must be greater than the previous key's {}", i,
                                     a.keys[i].frame, a.keys[i - 1].frame));
      if (a.repeat > 0 && a.keys[i].frame > a.repeat)
        throw SceneError(fmt::format("keys[{}].frame {} lies beyond the \"repeat\" period {}", i, a.keys[i].frame,
                                     a.repeat));
    }
  } catch (const nlohmann::json::exception& e) {
    throw SceneError(path, 0, std::string("invalid JSON: ") + e.what());
  } catch (const std::exception& e) {
    if (detail::located(e)) throw;
    throw SceneError(path, 0, e.what());
  }
  return a;
}

bool scene_animated(const Scene& s) {
  auto any = [](const auto& v) { return std::any_of(v.begin(), v.end(), [](const auto& x) { return x.animation >= 0; }); };
  return any(s.meshes) || any(s.spheres) || any(s.point_lights) || any(s.spot_lights) || any(s.distant_lights) ||
         (s.environment && s.environment->animation >= 0);
}

bool lights_animated(const Scene& s) {
  auto any = [](const auto& v) {
    return std::any_of(v.begin(), v.end(), [](const auto& x) { return x.animation >= 0 && x.emission.has_value(); });
  };
  auto any_light = [](const auto& v) { return std::any_of(v.begin(), v.end(), [](const auto& l) { return l.animation >= 0; }); };
  return any(s.meshes) || any(s.spheres) || any_light(s.point_lights) || any_light(s.spot_lights) || any_light(s.distant_lights) ||
         (s.environment && s.environment->animation >= 0);
}

namespace {

// Spot lights move like point lights, their axis turning with them; a distant light's direction
// turns as the environment does (the translation of its key is ignored: it is infinitely far).
// Both scale their emission by the key's intensity.
void animate_delta_lights(const Scene& rest, const std::vector<Mat4>& xf, const std::vector<float>& gain, Scene& out) {
  for (size_t li = 0; li < rest.spot_lights.size(); ++li) {
    const SpotLight& r = rest.spot_lights[li];
    if (r.animation < 0) continue;
    const size_t a = size_t(r.animation);
    out.spot_lights[li].position = xf[a].apply_point(r.position);
    out.spot_lights[li].direction = normalize(xf[a].apply_vector(r.direction));
    out.spot_lights[li].intensity = r.intensity * gain[a];
  }
  for (size_t li = 0; li < rest.distant_lights.size(); ++li) {
    const DistantLight& r = rest.distant_lights[li];
    if (r.animation < 0) continue;
    const size_t a = size_t(r.animation);
    out.distant_lights[li].direction = normalize(xf[a].apply_vector(r.direction));
    out.distant_lights[li].radiance = r.radiance * gain[a];
  }
}

}  // namespace

void animate_scene(const Scene& rest, int frame, Scene& out) {
  if (out.meshes.size() != rest.meshes.size() || out.spheres.size() != rest.spheres.size() ||
      out.point_lights.size() != rest.point_lights.size() || out.spot_lights.size() != rest.spot_lights.size() ||
      out.distant_lights.size() != rest.distant_lights.size() || out.environment.has_value() != rest.environment.has_value())
    out = rest;  // first frame: everything; later frames rewrite only what moves
  std::vector<Mat4> xf(rest.animations.size()), inv(rest.animations.size());
  std::vector<float> gain(rest.animations.size());
  for (size_t i = 0; i < rest.animations.size(); ++i) {
    xf[i] = rest.animations[i].transform(frame);
    xf[i].inverse(inv[i]);
    gain[i] = rest.animations[i].intensity(frame);
  }
  for (size_t mi = 0; mi < rest.meshes.size(); ++mi) {
    const TriangleMesh& r = rest.meshes[mi];
    if (r.animation < 0) continue;
    TriangleMesh& m = out.meshes[mi];
    const size_t a = size_t(r.animation);
    for (size_t i = 0; i < r.positions.size(); ++i) m.positions[i] = xf[a].apply_point(r.positions[i]);
    for (size_t i = 0; i < r.normals.size(); ++i) m.normals[i] = normalize(Mat4::apply_normal_with_inverse(inv[a], r.normals[i]));
    if (r.emission) m.emission->radiance = r.emission->radiance * gain[a];
  }
  for (size_t si = 0; si < rest.spheres.size(); ++si) {
    const Sphere& r = rest.spheres[si];
    if (r.animation < 0) continue;
    out.spheres[si].center = xf[size_t(r.animation)].apply_point(r.center);
    if (r.emission) out.spheres[si].emission->radiance = r.emission->radiance * gain[size_t(r.animation)];
  }
  for (size_t li = 0; li < rest.point_lights.size(); ++li) {
    const PointLight& r = rest.point_lights[li];
    if (r.animation < 0) continue;
    out.point_lights[li].position = xf[size_t(r.animation)].apply_point(r.position);
    out.point_lights[li].intensity = r.intensity * gain[size_t(r.animation)];
  }
  animate_delta_lights(rest, xf, gain, out);
  if (rest.environment && rest.environment->animation >= 0) {
    const size_t a = size_t(rest.environment->animation);
    EnvironmentLight& e = *out.environment;
    Mat4 rot = xf[a];
    rot.m[0][3] = rot.m[1][3] = rot.m[2][3] = 0;  // an environment only turns
    e.world_from_light = rot * rest.environment->world_from_light;
    e.world_from_light.inverse(e.light_from_world);
    e.radiance = rest.environment->radiance * gain[a];
  }
}

Scene scene_at_frame(const Scene& rest, int frame) {
  Scene s;
  animate_scene(rest, frame, s);
  s.animations.clear();
  for (auto& m : s.meshes) m.animation = -1;
  for (auto& sp : s.spheres) sp.animation = -1;
  for (auto& l : s.point_lights) l.animation = -1;
  for (auto& l : s.spot_lights) l.animation = -1;
  for (auto& l : s.distant_lights) l.animation = -1;
  if (s.environment) s.environment->animation = -1;
  return s;
}

}  // namespace rl
