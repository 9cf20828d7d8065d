// The scene's emitters as one list for light sampling: one emitter per emissive triangle, per
// emissive sphere, per point light, and one for the environment. Selection by emitted power
// (alias table) or uniformly; point sampling per emitter; solid-angle pdfs for MIS.
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
#include <vector>

#include "core/math.h"
#include "core/sampling.h"
#include "scene/light_selection.h"
#include "scene/scene.h"

namespace rl {

inline constexpr uint32_t kNoEmitter = 0xffffffffu;

struct LightSample {
  Rgb radiance;       // emitted radiance arriving along -wi (intensity / dist^2 for point lights); NOT divided by pdf
  Vec3 wi;            // unit direction from the shading point toward the light
  float distance = 0; // to the light point (kInfinity for the environment)
  float pdf = 0;      // solid-angle pdf INCLUDING the selection probability; point lights: the selection probability
  bool is_delta = false;  // point light
  Vec3 position, normal;  // on the light (normal zero for point / environment; environment: position = wi)
  uint32_t emitter = kNoEmitter;
};

// pbrt-v4's equal-area square <-> sphere mapping (Clarberg 2008, "Fast Equal-Area Mapping of the
// (Hemi)Sphere using SIMD"); p in [0,1]^2. Exposed for tests and the scene loader.
Vec3 equal_area_square_to_sphere(Vec2 p);
Vec2 equal_area_sphere_to_square(Vec3 w);

// A point on an emitter drawn independently of any receiving point (ReSTIR DI's light
// candidates, Bitterli et al. 2020 §3: cheap to generate, reusable across pixels).
struct EmitterPoint {
  Vec3 position;   // on the emitter; the direction for the environment
  Vec3 normal;     // geometric normal (zero for point lights / environment)
  uint32_t emitter = 0xffffffffu;
  float pdf = 0;   // selection pmf x density in the emitter's measure: 1/area (triangles, spheres,
                   // uniform by area), solid angle (environment), 1 (point lights)
};

class Lights {
 public:
  enum class Kind : uint8_t { triangle, sphere, point, environment };

  Lights() = default;
  Lights(const Scene& scene, LightSelection selection);

  size_t emitter_count() const { return emitters_.size(); }
  bool empty() const { return emitters_.empty(); }

  // Sample a light for the shading point p: u_select picks the emitter (alias table over power, or
  // uniform), u the point on it. false = no sample (no lights, or zero radiance toward p).
  bool sample(Vec3 p, float u_select, Vec2 u, LightSample& out) const;
  // The two halves of sample(): the emitter (kNoEmitter when there is none; *pmf its selection
  // probability), then a point on emitter e for p, out.pdf WITHOUT the selection probability
  // (solid angle; point lights 1). Separate so that ReSTIR DI's light tiles can pre-select.
  uint32_t select_emitter(float u, float* pmf) const;
  bool sample_emitter(uint32_t e, Vec3 p, Vec2 u, LightSample& out) const;
  // Solid-angle pdf at p of sample() producing light_p on emitter e (with the selection pmf).
  // Point lights: 0. Environment emitter: light_p is taken as the direction (as in LightSample).
  // light_n is unused: the emitter's own geometric normal is used (the same as sample()).
  float pdf(uint32_t emitter, Vec3 p, Vec3 light_p, Vec3 light_n) const;
  // Receiver-independent sampling: emitter by the selection table, then uniform by area on
  // triangles and spheres (both sides of a sphere; the back is rejected later by its target),
  // importance-sampled direction for the environment, the position for point lights.
  bool sample_point(float u_select, Vec2 u, EmitterPoint& out) const;
  // Density of sample_point() at a point of emitter e (direction for the environment), same measure.
  float point_pdf(uint32_t emitter, Vec3 position) const;
  // Where a point on emitter e of `before` (the same scene's lights one frame earlier) is now: an
  // animated emitter carries its points along (same barycentrics on a triangle, same offset from a
  // sphere's centre, the point light's position, the environment direction turned with the map).
  // Rigid motion keeps area, so the map's Jacobian is 1 in the emitters' area measure. false when
  // e is not the same kind of emitter in both (the sample must be dropped).
  bool follow(uint32_t e, const Lights& before, Vec3& position, Vec3& normal) const;
  float environment_pdf(Vec3 dir) const;      // includes the selection probability; 0 without environment
  Rgb environment_radiance(Vec3 dir) const;   // radiance arriving from direction dir; 0 without environment
  bool has_environment() const { return env_emitter_ != kNoEmitter; }
  uint32_t environment_emitter() const { return env_emitter_; }

  uint32_t triangle_emitter(uint32_t mesh, uint32_t triangle) const;
  uint32_t sphere_emitter(uint32_t sphere) const;
  // Radiance leaving an emitter's surface point with (flip-resolved) geometric normal n toward w.
  // Environment emitter: environment_radiance(-w); point lights: 0.
  Rgb emitted(uint32_t emitter, Vec3 n, Vec3 w) const;
  float selection_pmf(uint32_t emitter) const;
  float power(uint32_t emitter) const { return emitter < emitters_.size() ? emitters_[emitter].power : 0.0f; }
  // Intensity I of a point light (0 for other emitters).
  Rgb point_intensity(uint32_t emitter) const {
    return emitter < emitters_.size() && emitters_[emitter].kind == Kind::point ? emitters_[emitter].radiance : Rgb(0);
  }
  Kind kind(uint32_t emitter) const { return emitters_[emitter].kind; }

 private:
  struct Emitter {
    Kind kind = Kind::triangle;
    Vec3 p0, p1, p2;      // triangle vertices; sphere: p0 = centre; point: p0 = position
    Vec3 n;               // triangle geometric normal
    float area = 0;       // triangle area; sphere: radius in `radius`
    float radius = 0;
    bool flip = false;    // sphere normals inward
    bool two_sided = false;
    Rgb radiance;         // L (area emitters) or I (point light)
    float power = 0;
  };
  bool sample_triangle(const Emitter& e, Vec3 p, Vec2 u, LightSample& out) const;
  bool sample_sphere(const Emitter& e, Vec3 p, Vec2 u, LightSample& out) const;
  bool sample_environment(Vec2 u, LightSample& out) const;
  float environment_pdf_unselected(Vec3 dir) const;
  // Radiance and unselected solid-angle pdf of the texel a world direction looks up, in one go.
  struct EnvLookup {
    Rgb radiance{0};
    float pdf = 0;
  };
  EnvLookup environment_lookup(Vec3 dir) const;
  Rgb emitted_by(const Emitter& e, Vec3 n, Vec3 w) const;

  std::vector<Emitter> emitters_;
  AliasTable selection_;
  std::vector<uint32_t> mesh_first_;     // per mesh: first emitter index or kNoEmitter
  std::vector<uint32_t> sphere_index_;   // per sphere: emitter index or kNoEmitter
  uint32_t env_emitter_ = kNoEmitter;

  // Environment
  EnvironmentLight::Mapping env_mapping_ = EnvironmentLight::Mapping::constant;
  Rgb env_scale_{0};
  Image env_image_;
  Mat4 env_world_from_light_, env_light_from_world_;
  // Texel selection ∝ luminance x (equirect) sin(theta): a row, then a column in that row (pbrt's
  // marginal / conditional split, PBR4 sec. A.5.6), with alias tables for O(1) sampling where a 2-D
  // CDF's binary searches cost more than the ray queries on env-lit scenes. Two levels, not one
  // table over all texels: one float u cannot pick one of W*H = 2^19 texels AND flip the alias
  // coin -- only 24 - 19 = 5 bits would be left for the coin, so the sampled texel frequencies were
  // off by up to 1/32 from the pmf (a -1.4 % bias in the courtyard-lit images, found against
  // Mitsuba 3). With one table per dimension each coin keeps >= 13 bits.
  AliasTable env_rows_;
  std::vector<AliasTable> env_cols_;
};

}  // namespace rl
