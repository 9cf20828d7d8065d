// The light tables from the scene (our code, following pbrt-v4's DiffuseAreaLight, PointLight,
// SpotLight, DistantLight and Uniform/ImageInfiniteLight; PBR4 ch. 6 and 12). The per-sample code: scene/lights_view_inl.h.
#include "scene/lights.h"

#include "scene/animation.h"

namespace rl {

namespace {

// Luminance-based heuristics never go negative (negative texels would break the alias table).
float positive_luminance(Rgb c) { return std::max(luminance(c), 0.0f); }

// Scene bounds, for the environment's power heuristic only (own computation on purpose).
Bounds3 scene_bounds(const Scene& scene) {
  Bounds3 bounds;
  for (const TriangleMesh& m : scene.meshes)
    for (Vec3 q : m.positions) bounds.extend(q);
  for (const Sphere& s : scene.spheres) {
    bounds.extend(s.center - Vec3(s.radius));
    bounds.extend(s.center + Vec3(s.radius));
  }
  return bounds;
}

LightEmitter triangle_light(const TriangleMesh& m, uint32_t t) {
  LightEmitter e;
  e.kind = LightKind::triangle;
  e.p0 = m.positions[m.indices[3 * t]];
  e.p1 = m.positions[m.indices[3 * t + 1]];
  e.p2 = m.positions[m.indices[3 * t + 2]];
  e.area = 0.5f * length(cross(e.p1 - e.p0, e.p2 - e.p0));
  e.n = triangle_normal(m, t);
  if (!std::isfinite(e.area) || is_black(e.n)) e.area = 0;
  e.two_sided = m.emission->two_sided;
  e.radiance = m.emission->radiance;
  // Phi = pi A L (Lambertian emitter, PBR4 DiffuseAreaLight::Phi), twice when two-sided.
  e.power = positive_luminance(e.radiance) * e.area * kPi * (e.two_sided ? 2.0f : 1.0f);
  return e;
}

LightEmitter sphere_light(const Sphere& s) {
  LightEmitter e;
  e.kind = LightKind::sphere;
  e.p0 = s.center;
  e.radius = std::fabs(s.radius);
  e.area = 4 * kPi * e.radius * e.radius;
  e.flip = s.flip_normal;
  e.two_sided = s.emission->two_sided;
  e.radiance = s.emission->radiance;
  // Phi = pi A L with A = 4 pi r^2.
  e.power = positive_luminance(e.radiance) * e.area * kPi * (e.two_sided ? 2.0f : 1.0f);
  if (!std::isfinite(e.power)) e.power = 0;
  return e;
}

LightEmitter point_light(const PointLight& pl) {
  LightEmitter e;
  e.kind = LightKind::point;
  e.p0 = pl.position;
  e.radiance = pl.intensity;
  e.power = 4 * kPi * positive_luminance(pl.intensity);  // Phi = 4 pi I (PBR4 PointLight::Phi)
  return e;
}

LightEmitter spot_light(const SpotLight& sl) {
  LightEmitter e;
  e.kind = LightKind::spot;
  e.p0 = sl.position;
  e.n = sl.direction;
  e.radiance = sl.intensity;
  e.cos_falloff_start = sl.cos_falloff_start();
  e.cos_falloff_end = sl.cos_falloff_end();
  // Phi = I 2 pi ((1 - cos_start) + (cos_start - cos_end) / 2): the full cone's solid angle plus the
  // smoothstep band's integral, which is half of its solid angle (PBR4 SpotLight::Phi).
  e.power = positive_luminance(sl.intensity) * 2 * kPi *
            ((1 - e.cos_falloff_start) + (e.cos_falloff_start - e.cos_falloff_end) / 2);
  if (!std::isfinite(e.power)) e.power = 0;
  return e;
}

// The radius of the scene's bounding sphere (1 for an empty or degenerate scene): the power
// heuristics of the lights at infinity (pbrt-v4's Preprocess(sceneBounds)).
float scene_radius(const Bounds3& bounds) {
  float r = bounds.empty() ? 1.0f : 0.5f * length(bounds.diagonal());
  if (!(r > 0) || !std::isfinite(r)) r = 1.0f;
  return r;
}

LightEmitter distant_light(const DistantLight& dl, const Bounds3& bounds) {
  LightEmitter e;
  e.kind = LightKind::distant;
  e.p0 = dl.direction;
  e.radiance = dl.radiance;
  // Selection heuristic: the flux of L through the scene's bounding disk, Phi = pi r^2 L (PBR4 DistantLight::Phi).
  const float r = scene_radius(bounds);
  e.power = kPi * r * r * positive_luminance(dl.radiance);
  if (!std::isfinite(e.power)) e.power = 0;
  return e;
}

LightEmitter environment_light(const Bounds3& bounds, float avg) {
  LightEmitter e;
  e.kind = LightKind::environment;
  // Selection heuristic only: the flux of radiance avg through the scene's bounding sphere,
  // Phi = 4 pi * pi r^2 * L_avg (PBR4 UniformInfiniteLight::Phi / ImageInfiniteLight::Phi).
  const float r = scene_radius(bounds);
  e.power = 4 * kPi * kPi * r * r * avg;
  if (!std::isfinite(e.power)) e.power = 0;
  return e;
}

// An environment map's sampling tables (Lights::Tables' env_rows, env_col_*, env_texels).
struct EnvTables {
  AliasTable rows;
  std::vector<AliasBin> col_bins;
  std::vector<float> col_pmfs;
  std::vector<uint32_t> col_offsets;
  std::vector<EnvTexel> texels;
};

// Per-texel selection weights, row by row; *avg: the scaled map's mean luminance over the sphere.
std::vector<float> env_weights(const Image& image, Rgb scale, EnvironmentLight::Mapping mapping, float* avg) {
  const int w = image.width, h = image.height;
  std::vector<float> f(size_t(w) * size_t(h));
  double sum = 0, wsum = 0;
  for (int y = 0; y < h; ++y) {
    // Equirect: texel solid angle is proportional to sin(theta) (row centre).
    float jac = mapping == EnvironmentLight::Mapping::equirect ? std::sin(kPi * (float(y) + 0.5f) / float(h)) : 1.0f;
    for (int x = 0; x < w; ++x) {
      float l = positive_luminance(image.at(x, y) * scale);
      if (!std::isfinite(l)) l = 0;
      f[size_t(y) * size_t(w) + size_t(x)] = l * jac;
      sum += double(l) * jac;
      wsum += jac;
    }
  }
  *avg = wsum > 0 ? float(sum / wsum) : 0.0f;
  return f;
}

// The two-level selection: a column table per row (flattened), then the table over the rows.
void build_env_selection(const std::vector<float>& f, int w, int h, EnvTables& et) {
  std::vector<float> row_weight(size_t(h), 0.0f);
  et.col_offsets.assign(size_t(h) + 1, 0);
  for (int y = 0; y < h; ++y) {
    std::span<const float> row(f.data() + size_t(y) * size_t(w), size_t(w));
    const AliasTable cols(row);
    const AliasTableView cv = cols.view();
    et.col_bins.insert(et.col_bins.end(), cv.bins, cv.bins + cv.size);
    et.col_pmfs.insert(et.col_pmfs.end(), cv.pmfs, cv.pmfs + cv.size);
    et.col_offsets[size_t(y) + 1] = uint32_t(et.col_bins.size());
    row_weight[size_t(y)] = float(cols.total_weight());
  }
  et.rows = AliasTable(row_weight);
}

// Each texel's lookup result in one record (EnvTexel): the radiance as the map gives it,
// scaled, and the density of the two-level selection over (u, v).
void build_env_texels(const Image& image, Rgb scale, EnvTables& et) {
  const int w = image.width, h = image.height;
  et.texels.resize(size_t(w) * size_t(h));
  const AliasTableView rows = et.rows.view();
  for (int y = 0; y < h; ++y) {
    const uint32_t first = et.col_offsets[size_t(y)], end = et.col_offsets[size_t(y) + 1];
    const AliasTableView cols{et.col_bins.data() + first, et.col_pmfs.data() + first, end - first};
    for (int x = 0; x < w; ++x) {
      const Rgb v = image.at(x, y) * scale;
      et.texels[size_t(y) * size_t(w) + size_t(x)] = {is_finite(v) ? max(v, Rgb(0)) : Rgb(0),
                                                       rows.pmf(uint32_t(y)) * cols.pmf(uint32_t(x)) * float(w) * float(h)};
    }
  }
}

}  // namespace

Lights::Lights(const Scene& scene, LightSelection selection) {
  t_.mesh_first.assign(scene.meshes.size(), kNoEmitter);
  for (size_t mi = 0; mi < scene.meshes.size(); ++mi) {
    const TriangleMesh& m = scene.meshes[mi];
    if (!m.emission) continue;
    t_.mesh_first[mi] = uint32_t(t_.emitters.size());
    for (uint32_t t = 0; t < m.triangle_count(); ++t) t_.emitters.push_back(triangle_light(m, t));
  }
  t_.sphere_index.assign(scene.spheres.size(), kNoEmitter);
  for (size_t si = 0; si < scene.spheres.size(); ++si) {
    const Sphere& s = scene.spheres[si];
    if (!s.emission) continue;
    t_.sphere_index[si] = uint32_t(t_.emitters.size());
    t_.emitters.push_back(sphere_light(s));
  }
  for (const PointLight& pl : scene.point_lights) t_.emitters.push_back(point_light(pl));
  for (const SpotLight& sl : scene.spot_lights) t_.emitters.push_back(spot_light(sl));
  if (!scene.distant_lights.empty()) {
    const Bounds3 bounds = scene_bounds(scene);
    for (const DistantLight& dl : scene.distant_lights) t_.emitters.push_back(distant_light(dl, bounds));
  }
  if (scene.environment) {
    const EnvironmentLight& env = *scene.environment;
    t_.env_mapping = env.mapping;
    t_.env_scale = env.radiance;
    t_.env_world_from_light = env.world_from_light;
    t_.env_light_from_world = env.light_from_world;
    float avg = positive_luminance(t_.env_scale);
    if (t_.env_mapping != EnvironmentLight::Mapping::constant && env.image.empty()) t_.env_mapping = EnvironmentLight::Mapping::constant;
    if (t_.env_mapping != EnvironmentLight::Mapping::constant) {
      const Image& image = env.image;
      t_.env_width = image.width, t_.env_height = image.height;
      EnvTables et;
      build_env_selection(env_weights(image, t_.env_scale, t_.env_mapping, &avg), image.width, image.height, et);
      build_env_texels(image, t_.env_scale, et);
      t_.env_rows = std::move(et.rows);
      t_.env_col_bins = std::move(et.col_bins);
      t_.env_col_pmfs = std::move(et.col_pmfs);
      t_.env_col_offsets = std::move(et.col_offsets);
      t_.env_texels = std::move(et.texels);
    }
    t_.env_emitter = uint32_t(t_.emitters.size());
    t_.emitters.push_back(environment_light(scene_bounds(scene), avg));
  }
  std::vector<float> weights(t_.emitters.size());
  for (size_t i = 0; i < t_.emitters.size(); ++i) weights[i] = selection == LightSelection::power ? t_.emitters[i].power : 1.0f;
  t_.selection = AliasTable(weights);
  t_.fixed = !lights_animated(scene);
  repoint();
}

void Lights::repoint() {
  LightsView& v = view_;
  v.emitters = t_.emitters.data();
  v.num_emitters = uint32_t(t_.emitters.size());
  v.selection = t_.selection.view();
  v.mesh_first = t_.mesh_first.data();
  v.num_meshes = uint32_t(t_.mesh_first.size());
  v.sphere_index = t_.sphere_index.data();
  v.num_spheres = uint32_t(t_.sphere_index.size());
  v.env_emitter = t_.env_emitter;
  v.fixed = t_.fixed;
  v.env_mapping = t_.env_mapping;
  v.env_scale = t_.env_scale;
  v.env_texels = t_.env_texels.data();
  v.env_width = t_.env_width;
  v.env_height = t_.env_height;
  v.env_world_from_light = t_.env_world_from_light;
  v.env_light_from_world = t_.env_light_from_world;
  v.env_rows = t_.env_rows.view();
  v.env_col_bins = t_.env_col_bins.data();
  v.env_col_pmfs = t_.env_col_pmfs.data();
  v.num_env_col_entries = uint32_t(t_.env_col_bins.size());
  v.env_col_offsets = t_.env_col_offsets.data();
  v.num_env_col_offsets = uint32_t(t_.env_col_offsets.size());
}

bool Lights::follow(uint32_t idx, const Lights& before, Vec3& position, Vec3& normal) const {
  return view_.follow(idx, before.view_, position, normal);
}

}  // namespace rl
