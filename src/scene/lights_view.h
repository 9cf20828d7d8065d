// The per-sample half of Lights (scene/lights.h) as a flat, trivially copyable view: selection,
// point sampling and pdfs of the scene's emitters, callable from the host and from CUDA device code
// (RESTIR_HD; ARCHITECTURE.md, "Backends"). Lights builds the tables from the Scene and owns them;
// LightsView only points into them, and every Lights per-sample method forwards here (one
// implementation). The contracts of the functions are documented on Lights' forwarders.
//
// Building a device copy (the CUDA backend): every array the view reads is a public pointer field
// with its element count next to it (the table below). Copy each array to device memory
// (cudaMemcpy of count * sizeof(element) bytes), then copy the host view and replace each pointer
// with its device array; the scalar fields (env_mapping, env_scale, the two Mat4, env_emitter) and
// the counts are copied as they are. The result is passed to kernels by value.
//
//   pointer                  element          count
//   emitters                 LightEmitter     num_emitters
//   selection.bins           AliasBin         selection.size
//   selection.pmfs           float            selection.size
//   mesh_first               uint32_t         num_meshes
//   sphere_index             uint32_t         num_spheres
//   env_texels               EnvTexel         env_width * env_height (0 for a constant environment)
//   env_rows.bins            AliasBin         env_rows.size
//   env_rows.pmfs            float            env_rows.size
//   env_col_bins             AliasBin         num_env_col_entries
//   env_col_pmfs             float            num_env_col_entries
//   env_col_offsets          uint32_t         num_env_col_offsets (env_height + 1, or 0)
//
// A view is valid as long as the Lights it came from is alive and unchanged (Lights re-points its
// view when it is copied or moved; take view() again after that).
//
// Conventions
// - Triangle geometric normal: scene.h's triangle_normal() (normalize(cross(p1 - p0, p2 - p0)),
//   negated when flip_normal; shading normals decide when present). Sphere: (p - c) / r, negated
//   when flip_normal. Emission leaves on the normal's side only, unless two_sided.
// - A sample that would carry no radiance (the back of a one-sided emitter, a zero-area triangle,
//   a degenerate configuration) is reported as "no sample" (false), and pdf() is 0 for exactly
//   those points, so pdf() is the density of the samples sample() returns.
// - Environment maps (light space, then world_from_light):
//   * equirect (pbrt-v3 InfiniteAreaLight convention, +z up in light space):
//     u = phi / 2pi with phi = atan2(y, x) in [0, 2pi), v = theta / pi with theta = acos(z);
//     texel (floor(u W), floor(v H)), row 0 at the top of the image (v = 0 is +z).
//     Sampling density over (u, v) is luminance * sin(theta_row centre); pdf_dir = pdf_uv / (2 pi^2 sin theta).
//   * equal_area: pbrt-v4's equal-area octahedral map (Clarberg 2008), (u, v) = EqualAreaSphereToSquare(w),
//     texel (floor(u W), floor(v H)) with row 0 at v = 0 (pbrt-v4 image lookup); pdf_dir = pdf_uv / 4pi.
//   * Nearest-texel lookup: radiance is piecewise constant on the texels, so the piecewise-constant
//     sampling pdf is exactly proportional to the luminance (times the mapping's Jacobian).
//   * constant: uniform sphere sampling, pdf 1 / 4pi.
#pragma once
#include <cstdint>

#include "core/math.h"
#include "core/sampling.h"
#include "scene/scene.h"

namespace rl {

inline constexpr uint32_t kNoEmitter = 0xffffffffu;

struct LightSample {
  Rgb radiance;       // emitted radiance arriving along -wi (intensity / dist^2 for point and spot lights); NOT divided by pdf
  Vec3 wi;            // unit direction from the shading point toward the light
  float distance = 0; // to the light point (kInfinity for the environment and distant lights)
  float pdf = 0;      // solid-angle pdf INCLUDING the selection probability; delta lights: the selection probability
  bool is_delta = false;  // point, spot or distant light (LightsView::is_delta)
  Vec3 position, normal;  // on the light (normal zero for delta lights / environment; environment, distant: position = wi)
  uint32_t emitter = kNoEmitter;
};

// A point on an emitter drawn independently of any receiving point (ReSTIR DI's light
// candidates, Bitterli et al. 2020 §3: cheap to generate, reusable across pixels).
struct EmitterPoint {
  Vec3 position;   // on the emitter; the direction toward the light for the environment and distant lights
  Vec3 normal;     // geometric normal (zero for delta lights / environment)
  uint32_t emitter = 0xffffffffu;
  float pdf = 0;   // selection pmf x density in the emitter's measure: 1/area (triangles, spheres,
                   // uniform by area), solid angle (environment), 1 (point, spot, distant: counting)
};

// Delta lights (point, spot: a delta in position; distant: a delta in direction) are reached by
// light sampling only: no ray hits them, so BSDF sampling has density 0 for them, and their sample
// measure is counting (pdf = the selection pmf). Lights at infinity (environment, distant) keep a
// direction where the others keep a position, and their shadow rays are unbounded.
enum class LightKind : uint8_t { triangle, sphere, point, environment, spot, distant };

// One texel of an environment map with what a lookup returns: its radiance (scaled, negative and
// non-finite values zeroed) and its density over the map's (u, v) square (row pmf x column pmf x
// W x H). One record instead of three arrays, so that a lookup reads one cache line: on a
// 512x256 map the three scattered reads were a sixth of a ReSTIR PT frame (teapots).
struct EnvTexel {
  Rgb radiance{0};
  float pdf_uv = 0;
};

struct LightEmitter {
  LightKind kind = LightKind::triangle;
  bool flip = false;    // sphere normals inward
  bool two_sided = false;
  Vec3 p0, p1, p2;      // triangle vertices; sphere: p0 = centre; point, spot: p0 = position;
                        // distant: p0 = unit direction toward the light
  Vec3 n;               // triangle geometric normal; spot: unit cone axis
  float area = 0;       // triangle area; sphere: radius in `radius`
  float radius = 0;
  float cos_falloff_start = 1, cos_falloff_end = 1;  // spot: cosines of the full-intensity and outer cone
  Rgb radiance;         // L (area emitters, distant) or I (point, spot: on the axis)
  float power = 0;
};

namespace lights_detail {

inline constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;

RESTIR_HD inline bool finite_positive(float v) { return v > 0 && std::isfinite(v); }

}  // namespace lights_detail

// pbrt-v4's spot falloff (SpotLight::I): SmoothStep(cos_end, cos_start, cos_theta) -- 0 outside
// the outer cone (cos_theta <= cos_end), 1 inside the full-intensity cone (cos_theta >= cos_start),
// 3t^2 - 2t^3 with t = (cos_theta - cos_end) / (cos_start - cos_end) between; a hard edge when the
// two cones coincide (conedeltaangle 0).
RESTIR_HD inline float spot_falloff(float cos_theta, float cos_end, float cos_start) {
  if (cos_end == cos_start) return cos_theta < cos_end ? 0.0f : 1.0f;
  const float t = clamp((cos_theta - cos_end) / (cos_start - cos_end), 0.0f, 1.0f);
  return t * t * (3 - 2 * t);
}

namespace lights_detail {

// Light-space direction <-> equirect (u, v) (pbrt-v3 InfiniteAreaLight: u = phi / 2pi, v = theta / pi).
RESTIR_HD inline Vec2 equirect_uv(Vec3 w) {
  float phi = std::atan2(w.y, w.x);
  if (phi < 0) phi += 2 * kPi;
  float theta = std::acos(clamp(w.z, -1.0f, 1.0f));
  const float one_minus_epsilon = kOneMinusEpsilon;  // a local: std::min binds references (device code)
  return {std::min(phi * kInv2Pi, one_minus_epsilon), std::min(theta * kInvPi, one_minus_epsilon)};
}

}  // namespace lights_detail

// pbrt-v4's equal-area square <-> sphere mapping (Clarberg 2008, "Fast Equal-Area Mapping of the
// (Hemi)Sphere using SIMD"); p in [0,1]^2. Exposed for tests and the scene loader.
//
// pbrt-v4 EqualAreaSquareToSphere (Clarberg 2008): the signed distance to the square's diagonal
// gives z = +-(1 - r^2); the position along the diamond edge gives phi; |(x, y)| = r sqrt(2 - r^2).
RESTIR_HD inline Vec3 equal_area_square_to_sphere(Vec2 p) {
  float u = 2 * p.x - 1, v = 2 * p.y - 1;
  float up = std::fabs(u), vp = std::fabs(v);
  float signed_distance = 1 - (up + vp);
  float d = std::fabs(signed_distance);
  float r = 1 - d;
  float phi = (r == 0 ? 1 : (vp - up) / r + 1) * kPi / 4;
  float z = std::copysign(1 - r * r, signed_distance);
  float cos_phi = std::copysign(std::cos(phi), u);
  float sin_phi = std::copysign(std::sin(phi), v);
  float s = r * safe_sqrt(2 - r * r);
  return {cos_phi * s, sin_phi * s, z};
}

// Inverse of the above (pbrt-v4 EqualAreaSphereToSquare; std::atan instead of its polynomial).
RESTIR_HD inline Vec2 equal_area_sphere_to_square(Vec3 w) {
  float x = std::fabs(w.x), y = std::fabs(w.y), z = std::fabs(w.z);
  float r = safe_sqrt(1 - z);
  float a = std::max(x, y), b = std::min(x, y);
  b = a == 0 ? 0 : b / a;
  float phi = std::atan(b) * 2 * kInvPi;
  if (x < y) phi = 1 - phi;
  float v = phi * r;
  float u = r - v;
  if (w.z < 0) {
    const float t = u;  // swap u and v
    u = v;
    v = t;
    u = 1 - u;
    v = 1 - v;
  }
  u = std::copysign(u, w.x);
  v = std::copysign(v, w.y);
  return {clamp(0.5f * (u + 1), 0.0f, lights_detail::kOneMinusEpsilon),
          clamp(0.5f * (v + 1), 0.0f, lights_detail::kOneMinusEpsilon)};
}

struct LightsView {
  // Emitters (one per emissive triangle, emissive sphere, point, spot and distant light, and the environment).
  const LightEmitter* emitters = nullptr;
  uint32_t num_emitters = 0;
  AliasTableView selection;                 // over the emitters: by power or uniform
  const uint32_t* mesh_first = nullptr;     // per mesh: first emitter index or kNoEmitter
  uint32_t num_meshes = 0;
  const uint32_t* sphere_index = nullptr;   // per sphere: emitter index or kNoEmitter
  uint32_t num_spheres = 0;
  uint32_t env_emitter = kNoEmitter;
  // No emitter moves or changes over the sequence (animation.h's lights_animated is false). Then
  // what a sample keeps of the lights (ReSTIR PT's environment radiance and density at x_n, see
  // pt_path.h) holds in every frame, not only in the one that made the sample.
  bool fixed = true;

  // Environment
  EnvironmentLight::Mapping env_mapping = EnvironmentLight::Mapping::constant;
  Rgb env_scale{0};
  const EnvTexel* env_texels = nullptr;     // row-major, row 0 at the top (as Image::pixels)
  int env_width = 0, env_height = 0;
  Mat4 env_world_from_light, env_light_from_world;
  // Texel selection (see Lights' tables): env_rows picks the row y, then row y's column table is
  // the entries [env_col_offsets[y], env_col_offsets[y + 1]) of env_col_bins / env_col_pmfs (empty
  // for a row of zero weight).
  AliasTableView env_rows;
  const AliasBin* env_col_bins = nullptr;
  const float* env_col_pmfs = nullptr;
  uint32_t num_env_col_entries = 0;
  const uint32_t* env_col_offsets = nullptr;
  uint32_t num_env_col_offsets = 0;

  RESTIR_HD uint32_t emitter_count() const { return num_emitters; }
  RESTIR_HD bool empty() const { return num_emitters == 0; }
  RESTIR_HD bool has_environment() const { return env_emitter != kNoEmitter; }
  RESTIR_HD uint32_t environment_emitter() const { return env_emitter; }
  RESTIR_HD LightKind kind(uint32_t emitter) const { return emitters[emitter].kind; }
  RESTIR_HD float power(uint32_t emitter) const { return emitter < num_emitters ? emitters[emitter].power : 0.0f; }
  RESTIR_HD Rgb point_intensity(uint32_t emitter) const {
    return emitter < num_emitters && emitters[emitter].kind == LightKind::point ? emitters[emitter].radiance : Rgb(0);
  }
  // Point, spot and distant lights: no ray reaches them (see LightKind).
  RESTIR_HD bool is_delta(uint32_t emitter) const {
    if (emitter >= num_emitters) return false;
    const LightKind k = emitters[emitter].kind;
    return k == LightKind::point || k == LightKind::spot || k == LightKind::distant;
  }
  // The environment and distant lights: a light point is a direction, shadow rays are unbounded.
  RESTIR_HD bool at_infinity(uint32_t emitter) const {
    if (emitter >= num_emitters) return false;
    const LightKind k = emitters[emitter].kind;
    return k == LightKind::environment || k == LightKind::distant;
  }
  // What a delta light sends toward a receiver in direction wi (unit, from the receiver toward the
  // light): the intensity I toward -wi for point and spot lights (to be divided by d^2), the
  // radiance L for a distant light (pbrt-v4 PointLight / SpotLight / DistantLight::SampleLi); 0 for
  // every other emitter. A distant light's wi is taken to be its direction (its only light point).
  RESTIR_HD Rgb delta_emission(uint32_t emitter, Vec3 wi) const;
  RESTIR_HD float selection_pmf(uint32_t emitter) const { return selection.pmf(emitter); }
  RESTIR_HD uint32_t triangle_emitter(uint32_t mesh, uint32_t triangle) const {
    if (mesh >= num_meshes || mesh_first[mesh] == kNoEmitter) return kNoEmitter;
    return mesh_first[mesh] + triangle;
  }
  RESTIR_HD uint32_t sphere_emitter(uint32_t sphere) const {
    return sphere < num_spheres ? sphere_index[sphere] : kNoEmitter;
  }
  // The emitter a ray hit (a SurfaceInteraction: is_sphere, geom, prim); kNoEmitter for a
  // surface that does not emit.
  template <class Interaction>
  RESTIR_HD uint32_t emitter_at(const Interaction& si) const {
    return si.is_sphere ? sphere_emitter(si.prim) : triangle_emitter(si.geom, si.prim);
  }
  // Row y's column table (y < env_height of an image environment).
  RESTIR_HD AliasTableView env_cols(uint32_t y) const {
    return {env_col_bins + env_col_offsets[y], env_col_pmfs + env_col_offsets[y],
            env_col_offsets[y + 1] - env_col_offsets[y]};
  }

  // Bodies in scene/lights_view_inl.h.
  RESTIR_HD bool sample(Vec3 p, float u_select, Vec2 u, LightSample& out) const;
  RESTIR_HD uint32_t select_emitter(float u, float* pmf) const;
  RESTIR_HD bool sample_emitter(uint32_t e, Vec3 p, Vec2 u, LightSample& out) const;
  RESTIR_HD float pdf(uint32_t emitter, Vec3 p, Vec3 light_p, Vec3 light_n) const;
  // env_radiance (optional) receives the environment's radiance along a sampled direction (from
  // the texel lookup that gave its density; untouched for other emitters).
  RESTIR_HD bool sample_point(float u_select, Vec2 u, EmitterPoint& out, Rgb* env_radiance = nullptr) const;
  // The same for emitter idx already selected with probability pmf (a light tile's entry).
  RESTIR_HD bool sample_point_on(uint32_t idx, float pmf, Vec2 u, EmitterPoint& out, Rgb* env_radiance = nullptr) const;
  RESTIR_HD float point_pdf(uint32_t emitter, Vec3 position) const;
  RESTIR_HD float environment_pdf(Vec3 dir) const;
  RESTIR_HD Rgb environment_radiance(Vec3 dir) const;
  // The environment along a world direction from one texel lookup (environment_radiance and
  // point_pdf(environment_emitter(), dir) each look it up): radiance, and density with the
  // selection pmf, equal to point_pdf's bit for bit. Zero without an environment.
  struct EnvironmentValue {
    Rgb radiance{0};
    float pdf = 0;
  };
  RESTIR_HD EnvironmentValue environment_value(Vec3 dir) const;
  RESTIR_HD Rgb emitted(uint32_t emitter, Vec3 n, Vec3 w) const;
  // The geometric normal of emitter e at a point `position` on it, the normal its sampling and a
  // ray hitting it report: a triangle's e.n, a sphere's outward (or, flipped, inward) radial unit
  // vector; zero for point lights and the environment. Lets a light point be stored without its
  // normal (ReSTIR DI's 32-byte reservoir, RTXDI's packed reservoir keeps no normal either).
  RESTIR_HD Vec3 normal_at(uint32_t emitter, Vec3 position) const;
  // Where a point on emitter e of `before` (the same scene's lights one frame earlier) is now: an
  // animated emitter carries its points along (same barycentrics on a triangle, same offset from a
  // sphere's centre, a point or spot light's position, a distant light's direction, the environment
  // direction turned with the map).
  // Rigid motion keeps area, so the map's Jacobian is 1 in the emitters' area measure. false when
  // e is not the same kind of emitter in both (the sample must be dropped).
  RESTIR_HD bool follow(uint32_t e, const LightsView& before, Vec3& position, Vec3& normal) const;

 private:
  // Radiance and unselected solid-angle pdf of the texel a world direction looks up, in one go.
  struct EnvLookup {
    Rgb radiance{0};
    float pdf = 0;
  };
  RESTIR_HD bool sample_triangle(const LightEmitter& e, Vec3 p, Vec2 u, LightSample& out) const;
  RESTIR_HD bool sample_sphere(const LightEmitter& e, Vec3 p, Vec2 u, LightSample& out) const;
  RESTIR_HD bool sample_environment(Vec2 u, LightSample& out) const;
  RESTIR_HD float environment_pdf_unselected(Vec3 dir) const;
  RESTIR_HD EnvLookup environment_lookup(Vec3 dir) const;
  RESTIR_HD Rgb emitted_by(const LightEmitter& e, Vec3 n, Vec3 w) const;
};

}  // namespace rl

#include "scene/lights_view_inl.h"
