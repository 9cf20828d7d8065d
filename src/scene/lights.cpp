// Light selection and sampling (our code, following pbrt-v4's DiffuseAreaLight, Triangle/Sphere
// ::Sample(ctx, u), PointLight and Uniform/ImageInfiniteLight; PBR4 ch. 6 and 12).
#include "scene/lights.h"

namespace rl {

namespace {

constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;

bool finite_positive(float v) { return v > 0 && std::isfinite(v); }

// Luminance-based heuristics never go negative (negative texels would break the alias table).
float positive_luminance(Rgb c) { return std::max(luminance(c), 0.0f); }

// Light-space direction <-> equirect (u, v) (pbrt-v3 InfiniteAreaLight: u = phi / 2pi, v = theta / pi).
Vec2 equirect_uv(Vec3 w) {
  float phi = std::atan2(w.y, w.x);
  if (phi < 0) phi += 2 * kPi;
  float theta = std::acos(clamp(w.z, -1.0f, 1.0f));
  return {std::min(phi * kInv2Pi, kOneMinusEpsilon), std::min(theta * kInvPi, kOneMinusEpsilon)};
}


}  // namespace

// pbrt-v4 EqualAreaSquareToSphere (Clarberg 2008): the signed distance to the square's diagonal
// gives z = +-(1 - r^2); the position along the diamond edge gives phi; |(x, y)| = r sqrt(2 - r^2).
Vec3 equal_area_square_to_sphere(Vec2 p) {
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
Vec2 equal_area_sphere_to_square(Vec3 w) {
  float x = std::fabs(w.x), y = std::fabs(w.y), z = std::fabs(w.z);
  float r = safe_sqrt(1 - z);
  float a = std::max(x, y), b = std::min(x, y);
  b = a == 0 ? 0 : b / a;
  float phi = std::atan(b) * 2 * kInvPi;
  if (x < y) phi = 1 - phi;
  float v = phi * r;
  float u = r - v;
  if (w.z < 0) {
    std::swap(u, v);
    u = 1 - u;
    v = 1 - v;
  }
  u = std::copysign(u, w.x);
  v = std::copysign(v, w.y);
  return {clamp(0.5f * (u + 1), 0.0f, kOneMinusEpsilon), clamp(0.5f * (v + 1), 0.0f, kOneMinusEpsilon)};
}

Lights::Lights(const Scene& scene, LightSelection selection) {
  // Scene bounds, for the environment's power heuristic only (own computation on purpose).
  Bounds3 bounds;
  mesh_first_.assign(scene.meshes.size(), kNoEmitter);
  for (size_t mi = 0; mi < scene.meshes.size(); ++mi) {
    const TriangleMesh& m = scene.meshes[mi];
    for (Vec3 q : m.positions) bounds.extend(q);
    if (!m.emission) continue;
    mesh_first_[mi] = uint32_t(emitters_.size());
    for (uint32_t t = 0; t < m.triangle_count(); ++t) {
      Emitter e;
      e.kind = Kind::triangle;
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
      emitters_.push_back(e);
    }
  }
  sphere_index_.assign(scene.spheres.size(), kNoEmitter);
  for (size_t si = 0; si < scene.spheres.size(); ++si) {
    const Sphere& s = scene.spheres[si];
    bounds.extend(s.center - Vec3(s.radius));
    bounds.extend(s.center + Vec3(s.radius));
    if (!s.emission) continue;
    sphere_index_[si] = uint32_t(emitters_.size());
    Emitter e;
    e.kind = Kind::sphere;
    e.p0 = s.center;
    e.radius = std::fabs(s.radius);
    e.area = 4 * kPi * e.radius * e.radius;
    e.flip = s.flip_normal;
    e.two_sided = s.emission->two_sided;
    e.radiance = s.emission->radiance;
    // Phi = pi A L with A = 4 pi r^2.
    e.power = positive_luminance(e.radiance) * e.area * kPi * (e.two_sided ? 2.0f : 1.0f);
    if (!std::isfinite(e.power)) e.power = 0;
    emitters_.push_back(e);
  }
  for (const PointLight& pl : scene.point_lights) {
    Emitter e;
    e.kind = Kind::point;
    e.p0 = pl.position;
    e.radiance = pl.intensity;
    e.power = 4 * kPi * positive_luminance(pl.intensity);  // Phi = 4 pi I (PBR4 PointLight::Phi)
    emitters_.push_back(e);
  }
  if (scene.environment) {
    const EnvironmentLight& env = *scene.environment;
    env_mapping_ = env.mapping;
    env_scale_ = env.radiance;
    env_world_from_light_ = env.world_from_light;
    env_light_from_world_ = env.light_from_world;
    float avg = positive_luminance(env_scale_);
    if (env_mapping_ != EnvironmentLight::Mapping::constant && env.image.empty()) env_mapping_ = EnvironmentLight::Mapping::constant;
    if (env_mapping_ != EnvironmentLight::Mapping::constant) {
      env_image_ = env.image;
      const int w = env_image_.width, h = env_image_.height;
      std::vector<float> f(size_t(w) * size_t(h));
      double sum = 0, wsum = 0;
      for (int y = 0; y < h; ++y) {
        // Equirect: texel solid angle is proportional to sin(theta) (row centre).
        float jac = env_mapping_ == EnvironmentLight::Mapping::equirect ? std::sin(kPi * (float(y) + 0.5f) / float(h)) : 1.0f;
        for (int x = 0; x < w; ++x) {
          float l = positive_luminance(env_image_.at(x, y) * env_scale_);
          if (!std::isfinite(l)) l = 0;
          f[size_t(y) * size_t(w) + size_t(x)] = l * jac;
          sum += double(l) * jac;
          wsum += jac;
        }
      }
      std::vector<float> row_weight(size_t(h), 0.0f);
      env_cols_.resize(size_t(h));
      for (int y = 0; y < h; ++y) {
        std::span<const float> row(f.data() + size_t(y) * size_t(w), size_t(w));
        env_cols_[size_t(y)] = AliasTable(row);
        row_weight[size_t(y)] = float(env_cols_[size_t(y)].total_weight());
      }
      env_rows_ = AliasTable(row_weight);
      avg = wsum > 0 ? float(sum / wsum) : 0.0f;
    }
    Emitter e;
    e.kind = Kind::environment;
    // Selection heuristic only: the flux of radiance avg through the scene's bounding sphere,
    // Phi = 4 pi * pi r^2 * L_avg (PBR4 UniformInfiniteLight::Phi / ImageInfiniteLight::Phi).
    float r = bounds.empty() ? 1.0f : 0.5f * length(bounds.diagonal());
    if (!(r > 0) || !std::isfinite(r)) r = 1.0f;
    e.power = 4 * kPi * kPi * r * r * avg;
    if (!std::isfinite(e.power)) e.power = 0;
    env_emitter_ = uint32_t(emitters_.size());
    emitters_.push_back(e);
  }
  std::vector<float> weights(emitters_.size());
  for (size_t i = 0; i < emitters_.size(); ++i) weights[i] = selection == LightSelection::power ? emitters_[i].power : 1.0f;
  selection_ = AliasTable(weights);
}

float Lights::selection_pmf(uint32_t emitter) const { return selection_.pmf(emitter); }

uint32_t Lights::triangle_emitter(uint32_t mesh, uint32_t triangle) const {
  if (mesh >= mesh_first_.size() || mesh_first_[mesh] == kNoEmitter) return kNoEmitter;
  return mesh_first_[mesh] + triangle;
}

uint32_t Lights::sphere_emitter(uint32_t sphere) const {
  return sphere < sphere_index_.size() ? sphere_index_[sphere] : kNoEmitter;
}

Rgb Lights::emitted_by(const Emitter& e, Vec3 n, Vec3 w) const {
  if (e.two_sided || dot(n, w) > 0) return e.radiance;
  return Rgb(0);
}

Rgb Lights::emitted(uint32_t emitter, Vec3 n, Vec3 w) const {
  if (emitter >= emitters_.size()) return Rgb(0);
  const Emitter& e = emitters_[emitter];
  switch (e.kind) {
    case Kind::triangle:
    case Kind::sphere: return emitted_by(e, n, w);
    case Kind::point: return Rgb(0);
    case Kind::environment: return environment_radiance(-w);
  }
  return Rgb(0);
}

bool Lights::sample_point(float u_select, Vec2 u, EmitterPoint& out) const {
  out = {};
  if (selection_.size() == 0) return false;
  float pmf = 0;
  const uint32_t idx = selection_.sample(u_select, &pmf);
  if (!(pmf > 0)) return false;
  const Emitter& e = emitters_[idx];
  out.emitter = idx;
  switch (e.kind) {
    case Kind::triangle: {
      if (!(e.area > 0)) return false;
      const Vec3 b = sample_uniform_triangle(u);
      out.position = e.p0 * b.x + e.p1 * b.y + e.p2 * b.z;
      out.normal = e.n;
      out.pdf = pmf / e.area;
      break;
    }
    case Kind::sphere: {
      const Vec3 n = sample_uniform_sphere(u);
      out.position = e.p0 + n * e.radius;
      out.normal = e.flip ? -n : n;
      out.pdf = pmf / (4 * kPi * e.radius * e.radius);
      break;
    }
    case Kind::point:
      out.position = e.p0;
      out.pdf = pmf;
      break;
    case Kind::environment: {
      LightSample ls;
      if (!sample_environment(u, ls)) return false;
      out.position = ls.wi;
      out.pdf = pmf * ls.pdf;
      break;
    }
  }
  return out.pdf > 0 && std::isfinite(out.pdf);
}

float Lights::point_pdf(uint32_t emitter, Vec3 position) const {
  if (emitter >= emitters_.size()) return 0;
  const Emitter& e = emitters_[emitter];
  const float pmf = selection_.pmf(emitter);
  switch (e.kind) {
    case Kind::triangle: return e.area > 0 ? pmf / e.area : 0.0f;
    case Kind::sphere: return pmf / (4 * kPi * e.radius * e.radius);
    case Kind::point: return pmf;
    case Kind::environment: return pmf * environment_pdf_unselected(position);
  }
  return 0;
}

bool Lights::sample(Vec3 p, float u_select, Vec2 u, LightSample& out) const {
  out = {};
  float pmf = 0;
  const uint32_t idx = select_emitter(u_select, &pmf);
  if (idx == kNoEmitter || !sample_emitter(idx, p, u, out)) return false;
  out.pdf *= pmf;
  return true;
}

uint32_t Lights::select_emitter(float u, float* pmf) const {
  *pmf = 0;
  if (selection_.size() == 0) return kNoEmitter;
  const uint32_t idx = selection_.sample(u, pmf);
  return *pmf > 0 ? idx : kNoEmitter;
}

bool Lights::follow(uint32_t idx, const Lights& before, Vec3& position, Vec3& normal) const {
  if (idx >= emitters_.size() || idx >= before.emitters_.size()) return false;
  const Emitter &now = emitters_[idx], &then = before.emitters_[idx];
  if (now.kind != then.kind) return false;
  switch (now.kind) {
    case Kind::triangle: {
      // Barycentrics of the point in the old triangle (Ericson 2004, 3.4), applied to the new one.
      const Vec3 v0 = then.p1 - then.p0, v1 = then.p2 - then.p0, v2 = position - then.p0;
      const float d00 = dot(v0, v0), d01 = dot(v0, v1), d11 = dot(v1, v1), d20 = dot(v2, v0), d21 = dot(v2, v1);
      const float den = d00 * d11 - d01 * d01;
      if (!(den > 0)) return false;
      const float b1 = (d11 * d20 - d01 * d21) / den, b2 = (d00 * d21 - d01 * d20) / den;
      position = now.p0 * (1 - b1 - b2) + now.p1 * b1 + now.p2 * b2;
      normal = now.n;
      return is_finite(position);
    }
    case Kind::sphere:
      position = now.p0 + (position - then.p0);
      normal = normalize(position - now.p0) * (now.flip ? -1.0f : 1.0f);
      return is_finite(position);
    case Kind::point:
      position = now.p0;
      return true;
    case Kind::environment:  // a direction: back into the old map's frame, out through the new one
      position = normalize(env_world_from_light_.apply_vector(before.env_light_from_world_.apply_vector(position)));
      return is_finite(position);
  }
  return false;
}

bool Lights::sample_emitter(uint32_t idx, Vec3 p, Vec2 u, LightSample& out) const {
  out = {};
  if (idx >= emitters_.size()) return false;
  const Emitter& e = emitters_[idx];
  bool ok = false;
  switch (e.kind) {
    case Kind::triangle: ok = sample_triangle(e, p, u, out); break;
    case Kind::sphere: ok = sample_sphere(e, p, u, out); break;
    case Kind::point: {
      Vec3 d = e.p0 - p;
      float dist2 = length_squared(d);
      if (!finite_positive(dist2)) break;
      float dist = std::sqrt(dist2);
      out.wi = d / dist;
      out.distance = dist;
      out.radiance = e.radiance / dist2;  // I / d^2 (PBR4 PointLight::SampleLi)
      out.pdf = 1;
      out.is_delta = true;
      out.position = e.p0;
      ok = is_finite(out.radiance);
      break;
    }
    case Kind::environment: ok = sample_environment(u, out); break;
  }
  if (!ok || !(out.pdf > 0) || !std::isfinite(out.pdf) || is_black(out.radiance)) {
    out = {};
    return false;
  }
  out.emitter = idx;
  return true;
}

// Uniform area sampling (Heitz 2019 barycentrics), converted to solid angle with the Jacobian
// dA -> dw: dw = |cos theta_light| dA / d^2, so pdf_w = pdf_A d^2 / |cos theta_light|
// (PBR4 sec. 4.2.3; Veach 1997 sec. 8.2).
bool Lights::sample_triangle(const Emitter& e, Vec3 p, Vec2 u, LightSample& out) const {
  if (!(e.area > 0)) return false;
  Vec3 b = sample_uniform_triangle(u);
  Vec3 q = e.p0 * b.x + e.p1 * b.y + e.p2 * b.z;
  Vec3 d = q - p;
  float dist2 = length_squared(d);
  if (!finite_positive(dist2)) return false;
  float dist = std::sqrt(dist2);
  Vec3 wi = d / dist;
  float cos_l = -dot(e.n, wi);
  if (cos_l == 0 || (!e.two_sided && cos_l < 0)) return false;
  out.pdf = dist2 / (e.area * std::fabs(cos_l));
  out.wi = wi;
  out.distance = dist;
  out.radiance = e.radiance;
  out.position = q;
  out.normal = e.n;
  return finite_positive(out.pdf);
}

// pbrt-v4 Sphere::Sample(ctx, u): outside the sphere, sample the cone of directions subtending it
// uniformly (pdf 1 / (2 pi (1 - cos theta_max)), the solid angle of a spherical cap; PBR4
// sec. 6.2.4), and compute the point on the sphere from the angle alpha at the centre (more
// robust than a ray intersection); for sin^2 theta_max < sin^2(1.5 deg) use the Taylor expansion
// 1 - cos = sin^2 / 2. Inside the sphere: uniform area sampling converted to solid angle.
bool Lights::sample_sphere(const Emitter& e, Vec3 p, Vec2 u, LightSample& out) const {
  const Vec3 c = e.p0;
  const float r = e.radius;
  if (!(r > 0)) return false;
  float dc2 = length_squared(p - c);
  Vec3 nrm;  // outward unit normal at the sampled point
  float pdf;
  if (dc2 <= r * r) {
    nrm = sample_uniform_sphere(u);
    Vec3 q = c + r * nrm;
    Vec3 d = q - p;
    float dist2 = length_squared(d);
    if (!finite_positive(dist2)) return false;
    float cos_l = std::fabs(dot(nrm, d)) / std::sqrt(dist2);
    if (cos_l == 0) return false;
    pdf = dist2 / (e.area * cos_l);
  } else {
    float dc = std::sqrt(dc2);
    float sin2_max = r * r / dc2, sin_max = std::sqrt(sin2_max);
    float cos_max = safe_sqrt(1 - sin2_max);
    float one_minus_cos_max = 1 - cos_max;
    float cos_t = (cos_max - 1) * u.x + 1;
    float sin2_t = 1 - cos_t * cos_t;
    if (sin2_max < 0.00068523f) {  // sin^2(1.5 deg)
      sin2_t = sin2_max * u.x;
      cos_t = std::sqrt(1 - sin2_t);
      one_minus_cos_max = sin2_max / 2;
    }
    // Angle alpha between -wc and the normal at the sampled point (law of sines / cosines).
    float cos_a = sin2_t / sin_max + cos_t * safe_sqrt(1 - sin2_t / sin2_max);
    float sin_a = safe_sqrt(1 - cos_a * cos_a);
    float phi = u.y * 2 * kPi;
    Frame f = Frame::from_normal((c - p) / dc);
    nrm = f.to_world(Vec3{-sin_a * std::cos(phi), -sin_a * std::sin(phi), -cos_a});
    pdf = 1 / (2 * kPi * one_minus_cos_max);
  }
  Vec3 q = c + r * nrm;
  Vec3 d = q - p;
  float dist2 = length_squared(d);
  if (!finite_positive(dist2)) return false;
  float dist = std::sqrt(dist2);
  Vec3 n = e.flip ? -nrm : nrm;
  out.wi = d / dist;
  if (!e.two_sided && dot(n, out.wi) >= 0) return false;  // back side of a one-sided emitter
  out.pdf = pdf;
  out.distance = dist;
  out.radiance = e.radiance;
  out.position = q;
  out.normal = n;
  return finite_positive(pdf);
}

bool Lights::sample_environment(Vec2 u, LightSample& out) const {
  Vec3 wl;
  if (env_mapping_ == EnvironmentLight::Mapping::constant) {
    wl = sample_uniform_sphere(u);
  } else {
    // Row, then column, then uniform in the texel's (u, v) cell (the tables' remapped u's):
    // pdf_uv = pmf_row * pmf_col * W * H.
    float pmf_y, pmf_x, fy, fx;
    const uint32_t y = env_rows_.sample(u.x, &pmf_y, &fy);
    if (!(pmf_y > 0)) return false;
    const uint32_t x = env_cols_[y].sample(u.y, &pmf_x, &fx);
    if (!(pmf_x > 0)) return false;
    const int w = env_image_.width, h = env_image_.height;
    const Vec2 uv{(float(x) + fx) / float(w), (float(y) + fy) / float(h)};
    if (env_mapping_ == EnvironmentLight::Mapping::equirect) {
      float theta = uv.y * kPi, phi = uv.x * 2 * kPi;
      float st = std::sin(theta);
      if (!(st > 0)) return false;
      wl = {st * std::cos(phi), st * std::sin(phi), std::cos(theta)};
    } else {
      wl = equal_area_square_to_sphere(uv);
    }
  }
  Vec3 w = env_world_from_light_.apply_vector(wl);
  float len = length(w);
  if (!finite_positive(len)) return false;
  w = w / len;
  // Report the pdf of the texel the final direction looks up (the same path as
  // environment_pdf / environment_radiance), so that sample() and pdf() agree exactly even when
  // rounding moves a direction sampled at a texel edge into the neighbouring texel.
  const EnvLookup look = environment_lookup(w);
  out.wi = w;
  out.pdf = look.pdf;
  out.distance = kInfinity;
  out.radiance = look.radiance;
  out.position = w;
  out.normal = Vec3(0);
  return finite_positive(look.pdf);
}

Lights::EnvLookup Lights::environment_lookup(Vec3 dir) const {
  EnvLookup r;
  if (env_emitter_ == kNoEmitter) return r;
  if (env_mapping_ == EnvironmentLight::Mapping::constant) return {env_scale_, kInv4Pi};
  Vec3 wl = env_light_from_world_.apply_vector(dir);
  float len = length(wl);
  if (!finite_positive(len)) return r;
  wl = wl / len;
  const bool equirect = env_mapping_ == EnvironmentLight::Mapping::equirect;
  const Vec2 uv = equirect ? equirect_uv(wl) : equal_area_sphere_to_square(wl);
  const int w = env_image_.width, h = env_image_.height;
  const int x = clamp(int(uv.x * float(w)), 0, w - 1), y = clamp(int(uv.y * float(h)), 0, h - 1);
  const size_t texel = size_t(y) * size_t(w) + size_t(x);
  const Rgb v = env_image_.pixels[texel] * env_scale_;
  r.radiance = is_finite(v) ? max(v, Rgb(0)) : Rgb(0);
  const float pdf_uv = env_rows_.pmf(uint32_t(y)) * env_cols_[size_t(y)].pmf(uint32_t(x)) * float(w) * float(h);
  if (equirect) {
    // Jacobian of (u, v) -> direction: 2 pi^2 sin(theta).
    float st = std::sqrt(wl.x * wl.x + wl.y * wl.y);
    r.pdf = st > 0 ? pdf_uv / (2 * kPi * kPi * st) : 0.0f;
  } else {
    r.pdf = pdf_uv * kInv4Pi;  // equal-area map: constant Jacobian 4 pi
  }
  if (!std::isfinite(r.pdf)) r.pdf = 0;
  return r;
}

Rgb Lights::environment_radiance(Vec3 dir) const { return environment_lookup(dir).radiance; }

float Lights::environment_pdf_unselected(Vec3 dir) const { return environment_lookup(dir).pdf; }

float Lights::environment_pdf(Vec3 dir) const {
  if (env_emitter_ == kNoEmitter) return 0;
  float pmf = selection_.pmf(env_emitter_);
  if (!(pmf > 0)) return 0;
  return pmf * environment_pdf_unselected(dir);
}

float Lights::pdf(uint32_t emitter, Vec3 p, Vec3 light_p, Vec3 /*light_n*/) const {
  if (emitter >= emitters_.size()) return 0;
  float pmf = selection_.pmf(emitter);
  if (!(pmf > 0)) return 0;
  const Emitter& e = emitters_[emitter];
  switch (e.kind) {
    case Kind::point: return 0;
    case Kind::environment: return environment_pdf(light_p);
    case Kind::triangle: {
      if (!(e.area > 0)) return 0;
      Vec3 d = light_p - p;
      float dist2 = length_squared(d);
      if (!finite_positive(dist2)) return 0;
      float cos_l = -dot(e.n, d) / std::sqrt(dist2);
      if (cos_l == 0 || (!e.two_sided && cos_l < 0)) return 0;
      float pdf = pmf * dist2 / (e.area * std::fabs(cos_l));
      return std::isfinite(pdf) ? pdf : 0.0f;
    }
    case Kind::sphere: {
      const float r = e.radius;
      if (!(r > 0)) return 0;
      Vec3 nrm = light_p - e.p0;
      float nl = length(nrm);
      if (!finite_positive(nl)) return 0;
      nrm = nrm / nl;
      Vec3 d = light_p - p;
      float dist2 = length_squared(d);
      if (!finite_positive(dist2)) return 0;
      Vec3 wi = d / std::sqrt(dist2);
      Vec3 n = e.flip ? -nrm : nrm;
      if (!e.two_sided && dot(n, wi) >= 0) return 0;
      float dc2 = length_squared(p - e.p0);
      float pdf;
      if (dc2 <= r * r) {
        float cos_l = std::fabs(dot(nrm, wi));
        if (cos_l == 0) return 0;
        pdf = dist2 / (e.area * cos_l);
      } else {
        float sin2_max = r * r / dc2;
        float one_minus_cos_max = sin2_max < 0.00068523f ? sin2_max / 2 : 1 - safe_sqrt(1 - sin2_max);
        pdf = 1 / (2 * kPi * one_minus_cos_max);
      }
      pdf *= pmf;
      return std::isfinite(pdf) ? pdf : 0.0f;
    }
  }
  return 0;
}

}  // namespace rl
