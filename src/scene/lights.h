// The scene's emitters as one list for light sampling: one emitter per emissive triangle, per
// emissive sphere, per point, spot and distant light, and one for the environment. Selection by emitted power
// (alias table) or uniformly; point sampling per emitter; solid-angle pdfs for MIS.
//
// The per-sample code lives in LightsView (scene/lights_view.h, with the conventions: normals,
// "no sample", environment mappings): flat and trivially copyable, so that the CUDA backend can
// call it. Lights builds and owns the tables the view points into; each per-sample method below is
// a one-line forward to view().
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

#include "core/math.h"
#include "core/sampling.h"
#include "scene/light_selection.h"
#include "scene/lights_view.h"
#include "scene/scene.h"

namespace rl {

class Lights {
 public:
  using Kind = LightKind;

  Lights() = default;
  Lights(const Scene& scene, LightSelection selection);
  // Copies and moves re-point the view at the new owner's tables.
  Lights(const Lights& other) : t_(other.t_) { repoint(); }
  Lights(Lights&& other) noexcept : t_(std::move(other.t_)) {
    repoint();
    other.repoint();
  }
  Lights& operator=(const Lights& other) {
    if (this != &other) {
      t_ = other.t_;
      repoint();
    }
    return *this;
  }
  Lights& operator=(Lights&& other) noexcept {
    if (this != &other) {
      t_ = std::move(other.t_);
      repoint();
      other.repoint();
    }
    return *this;
  }

  // The flat view the per-sample methods forward to (device-shaped; scene/lights_view.h). Valid
  // while this Lights is alive and not assigned to or moved from.
  const LightsView& view() const { return view_; }

  size_t emitter_count() const { return view_.emitter_count(); }
  bool empty() const { return view_.empty(); }

  // Sample a light for the shading point p: u_select picks the emitter (alias table over power, or
  // uniform), u the point on it. false = no sample (no lights, or zero radiance toward p).
  bool sample(Vec3 p, float u_select, Vec2 u, LightSample& out) const { return view_.sample(p, u_select, u, out); }
  // The two halves of sample(): the emitter (kNoEmitter when there is none; *pmf its selection
  // probability), then a point on emitter e for p, out.pdf WITHOUT the selection probability
  // (solid angle; point lights 1). Separate so that ReSTIR DI's light tiles can pre-select.
  uint32_t select_emitter(float u, float* pmf) const { return view_.select_emitter(u, pmf); }
  bool sample_emitter(uint32_t e, Vec3 p, Vec2 u, LightSample& out) const { return view_.sample_emitter(e, p, u, out); }
  // Solid-angle pdf at p of sample() producing light_p on emitter e (with the selection pmf).
  // Delta lights (point, spot, distant): 0. Environment emitter: light_p is taken as the direction (as in LightSample).
  // light_n is unused: the emitter's own geometric normal is used (the same as sample()).
  float pdf(uint32_t emitter, Vec3 p, Vec3 light_p, Vec3 light_n) const { return view_.pdf(emitter, p, light_p, light_n); }
  // Receiver-independent sampling: emitter by the selection table, then uniform by area on
  // triangles and spheres (both sides of a sphere; the back is rejected later by its target),
  // importance-sampled direction for the environment, the position for point and spot lights, the
  // direction for distant lights.
  bool sample_point(float u_select, Vec2 u, EmitterPoint& out) const { return view_.sample_point(u_select, u, out); }
  // Density of sample_point() at a point of emitter e (direction for the environment), same measure.
  float point_pdf(uint32_t emitter, Vec3 position) const { return view_.point_pdf(emitter, position); }
  // Where a point on emitter e of `before` (the same scene's lights one frame earlier) is now: an
  // animated emitter carries its points along (same barycentrics on a triangle, same offset from a
  // sphere's centre, a point or spot light's position, a distant light's direction, the environment
  // direction turned with the map).
  // Rigid motion keeps area, so the map's Jacobian is 1 in the emitters' area measure. false when
  // e is not the same kind of emitter in both (the sample must be dropped). Host only.
  bool follow(uint32_t e, const Lights& before, Vec3& position, Vec3& normal) const;
  // Includes the selection probability; 0 without environment.
  float environment_pdf(Vec3 dir) const { return view_.environment_pdf(dir); }
  // Radiance arriving from direction dir; 0 without environment.
  Rgb environment_radiance(Vec3 dir) const { return view_.environment_radiance(dir); }
  bool has_environment() const { return view_.has_environment(); }
  uint32_t environment_emitter() const { return view_.environment_emitter(); }

  uint32_t triangle_emitter(uint32_t mesh, uint32_t triangle) const { return view_.triangle_emitter(mesh, triangle); }
  uint32_t sphere_emitter(uint32_t sphere) const { return view_.sphere_emitter(sphere); }
  // Radiance leaving an emitter's surface point with (flip-resolved) geometric normal n toward w.
  // Environment emitter: environment_radiance(-w); point lights: 0.
  Rgb emitted(uint32_t emitter, Vec3 n, Vec3 w) const { return view_.emitted(emitter, n, w); }
  float selection_pmf(uint32_t emitter) const { return view_.selection_pmf(emitter); }
  float power(uint32_t emitter) const { return view_.power(emitter); }
  // Intensity I of a point light (0 for other emitters).
  Rgb point_intensity(uint32_t emitter) const { return view_.point_intensity(emitter); }
  // Point, spot and distant lights; the environment and distant lights; what a delta light sends
  // toward wi (LightsView's documentation).
  bool is_delta(uint32_t emitter) const { return view_.is_delta(emitter); }
  bool at_infinity(uint32_t emitter) const { return view_.at_infinity(emitter); }
  Rgb delta_emission(uint32_t emitter, Vec3 wi) const { return view_.delta_emission(emitter, wi); }
  Kind kind(uint32_t emitter) const { return view_.kind(emitter); }

 private:
  // The host-side tables (view_ points into them).
  struct Tables {
    std::vector<LightEmitter> emitters;
    AliasTable selection;
    std::vector<uint32_t> mesh_first;     // per mesh: first emitter index or kNoEmitter
    std::vector<uint32_t> sphere_index;   // per sphere: emitter index or kNoEmitter
    uint32_t env_emitter = kNoEmitter;
    bool fixed = true;  // LightsView::fixed

    // Environment
    EnvironmentLight::Mapping env_mapping = EnvironmentLight::Mapping::constant;
    Rgb env_scale{0};
    int env_width = 0, env_height = 0;  // the map's texels (its pixels live on in env_texels)
    Mat4 env_world_from_light, env_light_from_world;
    // Texel selection ∝ luminance x (equirect) sin(theta): a row, then a column in that row (pbrt's
    // marginal / conditional split, PBR4 sec. A.5.6), with alias tables for O(1) sampling where a 2-D
    // CDF's binary searches cost more than the ray queries on env-lit scenes. Two levels, not one
    // table over all texels: one float u cannot pick one of W*H = 2^19 texels AND flip the alias
    // coin -- only 24 - 19 = 5 bits would be left for the coin, so the sampled texel frequencies were
    // off by up to 1/32 from the pmf (a -1.4 % bias in the courtyard-lit images, found against
    // Mitsuba 3). With one table per dimension each coin keeps >= 13 bits.
    AliasTable env_rows;
    // The per-row column tables flattened: row y's bins and pmfs are the entries
    // [env_col_offsets[y], env_col_offsets[y + 1]) (none for a row of zero weight).
    std::vector<AliasBin> env_col_bins;
    std::vector<float> env_col_pmfs;
    std::vector<uint32_t> env_col_offsets;  // env_height + 1 entries (none for a constant environment)
    std::vector<EnvTexel> env_texels;       // per texel: radiance and density (lights_view.h)
  };
  // Points view_ at t_ (after construction, copies and moves).
  void repoint();

  Tables t_;
  LightsView view_;
};

}  // namespace rl
