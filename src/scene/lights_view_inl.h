// LightsView's per-sample bodies (included at the end of scene/lights_view.h; do not include
// directly). Light selection and sampling (our code, following pbrt-v4's DiffuseAreaLight,
// Triangle/Sphere ::Sample(ctx, u), PointLight, SpotLight, DistantLight and Uniform/ImageInfiniteLight;
// PBR4 ch. 6 and 12).
#pragma once
#include "scene/lights_view.h"

namespace rl {

RESTIR_HD inline Rgb LightsView::emitted_by(const LightEmitter& e, Vec3 n, Vec3 w) const {
  if (e.two_sided || dot(n, w) > 0) return e.radiance;
  return Rgb(0);
}

RESTIR_HD inline Rgb LightsView::emitted(uint32_t emitter, Vec3 n, Vec3 w) const {
  if (emitter >= num_emitters) return Rgb(0);
  const LightEmitter& e = emitters[emitter];
  switch (e.kind) {
    case LightKind::triangle:
    case LightKind::sphere: return emitted_by(e, n, w);
    case LightKind::point:
    case LightKind::spot:
    case LightKind::distant: return Rgb(0);  // delta lights: no surface to see
    case LightKind::environment: return environment_radiance(-w);
  }
  return Rgb(0);
}

RESTIR_HD inline Rgb LightsView::delta_emission(uint32_t emitter, Vec3 wi) const {
  if (emitter >= num_emitters) return Rgb(0);
  const LightEmitter& e = emitters[emitter];
  switch (e.kind) {
    case LightKind::point:
    case LightKind::distant: return e.radiance;
    case LightKind::spot: return e.radiance * spot_falloff(-dot(e.n, wi), e.cos_falloff_end, e.cos_falloff_start);
    default: return Rgb(0);
  }
}

RESTIR_HD inline Vec3 LightsView::normal_at(uint32_t emitter, Vec3 position) const {
  if (emitter >= num_emitters) return Vec3(0);
  const LightEmitter& e = emitters[emitter];
  switch (e.kind) {
    case LightKind::triangle: return e.n;
    case LightKind::sphere: {
      const Vec3 d = position - e.p0;
      const float len = length(d);
      if (!(len > 0)) return Vec3(0);
      return e.flip ? d / -len : d / len;
    }
    default: return Vec3(0);
  }
}

RESTIR_HD inline bool LightsView::sample_point(float u_select, Vec2 u, EmitterPoint& out, Rgb* env_radiance) const {
  out = {};
  if (selection.size == 0) return false;
  float pmf = 0;
  const uint32_t idx = selection.sample(u_select, &pmf);
  return sample_point_on(idx, pmf, u, out, env_radiance);
}

RESTIR_HD inline bool LightsView::sample_point_on(uint32_t idx, float pmf, Vec2 u, EmitterPoint& out, Rgb* env_radiance) const {
  out = {};
  if (!(pmf > 0) || idx >= num_emitters) return false;
  const LightEmitter& e = emitters[idx];
  out.emitter = idx;
  switch (e.kind) {
    case LightKind::triangle: {
      if (!(e.area > 0)) return false;
      const Vec3 b = sample_uniform_triangle(u);
      out.position = e.p0 * b.x + e.p1 * b.y + e.p2 * b.z;
      out.normal = e.n;
      out.pdf = pmf / e.area;
      break;
    }
    case LightKind::sphere: {
      const Vec3 n = sample_uniform_sphere(u);
      out.position = e.p0 + n * e.radius;
      out.normal = e.flip ? -n : n;
      out.pdf = pmf / (4 * kPi * e.radius * e.radius);
      break;
    }
    case LightKind::point:
    case LightKind::spot:
    case LightKind::distant:  // p0: the position, or the distant light's direction
      out.position = e.p0;
      out.pdf = pmf;
      break;
    case LightKind::environment: {
      LightSample ls;
      if (!sample_environment(u, ls)) return false;
      out.position = ls.wi;
      out.pdf = pmf * ls.pdf;
      if (env_radiance) *env_radiance = ls.radiance;
      break;
    }
  }
  return out.pdf > 0 && std::isfinite(out.pdf);
}

RESTIR_HD inline float LightsView::point_pdf(uint32_t emitter, Vec3 position) const {
  if (emitter >= num_emitters) return 0;
  const LightEmitter& e = emitters[emitter];
  const float pmf = selection.pmf(emitter);
  switch (e.kind) {
    case LightKind::triangle: return e.area > 0 ? pmf / e.area : 0.0f;
    case LightKind::sphere: return pmf / (4 * kPi * e.radius * e.radius);
    case LightKind::point:
    case LightKind::spot:
    case LightKind::distant: return pmf;
    case LightKind::environment: return pmf * environment_pdf_unselected(position);
  }
  return 0;
}

RESTIR_HD inline bool LightsView::sample(Vec3 p, float u_select, Vec2 u, LightSample& out) const {
  out = {};
  float pmf = 0;
  const uint32_t idx = select_emitter(u_select, &pmf);
  if (idx == kNoEmitter || !sample_emitter(idx, p, u, out)) return false;
  out.pdf *= pmf;
  return true;
}

RESTIR_HD inline uint32_t LightsView::select_emitter(float u, float* pmf) const {
  *pmf = 0;
  if (selection.size == 0) return kNoEmitter;
  const uint32_t idx = selection.sample(u, pmf);
  return *pmf > 0 ? idx : kNoEmitter;
}

RESTIR_HD inline bool LightsView::sample_emitter(uint32_t idx, Vec3 p, Vec2 u, LightSample& out) const {
  using lights_detail::finite_positive;
  out = {};
  if (idx >= num_emitters) return false;
  const LightEmitter& e = emitters[idx];
  bool ok = false;
  switch (e.kind) {
    case LightKind::triangle: ok = sample_triangle(e, p, u, out); break;
    case LightKind::sphere: ok = sample_sphere(e, p, u, out); break;
    case LightKind::point:
    case LightKind::spot: {
      Vec3 d = e.p0 - p;
      float dist2 = length_squared(d);
      if (!finite_positive(dist2)) break;
      float dist = std::sqrt(dist2);
      out.wi = d / dist;
      out.distance = dist;
      out.radiance = delta_emission(idx, out.wi) / dist2;  // I(-wi) / d^2 (PBR4 PointLight, SpotLight::SampleLi)
      out.pdf = 1;
      out.is_delta = true;
      out.position = e.p0;
      ok = is_finite(out.radiance);
      break;
    }
    case LightKind::distant:  // L from one direction: no 1/d^2 (PBR4 DistantLight::SampleLi)
      out.wi = e.p0;
      out.distance = kInfinity;
      out.radiance = e.radiance;
      out.pdf = 1;
      out.is_delta = true;
      out.position = e.p0;
      ok = is_finite(out.radiance);
      break;
    case LightKind::environment: ok = sample_environment(u, out); break;
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
RESTIR_HD inline bool LightsView::sample_triangle(const LightEmitter& e, Vec3 p, Vec2 u, LightSample& out) const {
  using lights_detail::finite_positive;
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
RESTIR_HD inline bool LightsView::sample_sphere(const LightEmitter& e, Vec3 p, Vec2 u, LightSample& out) const {
  using lights_detail::finite_positive;
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
    float sin_phi, cos_phi;  // phi = 2 pi u.y
    sincos_turns(u.y, sin_phi, cos_phi);
    Frame f = Frame::from_normal((c - p) / dc);
    nrm = f.to_world(Vec3{-sin_a * cos_phi, -sin_a * sin_phi, -cos_a});
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

RESTIR_HD inline bool LightsView::sample_environment(Vec2 u, LightSample& out) const {
  using lights_detail::finite_positive;
  Vec3 wl;
  if (env_mapping == EnvironmentLight::Mapping::constant) {
    wl = sample_uniform_sphere(u);
  } else {
    // Row, then column, then uniform in the texel's (u, v) cell (the tables' remapped u's):
    // pdf_uv = pmf_row * pmf_col * W * H.
    float pmf_y, fy, fx = 0;
    const uint32_t y = env_rows.sample(u.x, &pmf_y, &fy);
    if (!(pmf_y > 0)) return false;  // also: row y has a column table
    // The column's pmf is not read: an alias table never picks a zero-weight bin, and the texel's
    // own density (pdf_uv, looked up below) is 0 for one anyway. The read was a cache miss of its
    // own in a 2 MB table for a 1024x512 map.
    const uint32_t x = env_cols(y).sample(u.y, nullptr, &fx);
    const int w = env_width, h = env_height;
#ifndef __CUDA_ARCH__
    // The lookup at the end reads texel (x, y) (a neighbour only when rounding moves the direction
    // across an edge): fetching it now overlaps its cache miss with the trigonometry in between.
    // The miss was a third of this function's time (teapots, ReSTIR PT, 1024x512 map).
    prefetch_line(env_texels + size_t(y) * size_t(w) + size_t(x));
#endif
    const Vec2 uv{(float(x) + fx) / float(w), (float(y) + fy) / float(h)};
    if (env_mapping == EnvironmentLight::Mapping::equirect) {
      float theta = uv.y * kPi, phi = uv.x * 2 * kPi;
      float st = std::sin(theta);
      if (!(st > 0)) return false;
      wl = {st * std::cos(phi), st * std::sin(phi), std::cos(theta)};
    } else {
      wl = equal_area_square_to_sphere(uv);
    }
  }
  Vec3 w = env_world_from_light.apply_vector(wl);
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

RESTIR_HD inline LightsView::EnvLookup LightsView::environment_lookup(Vec3 dir) const {
  using lights_detail::finite_positive;
  EnvLookup r;
  if (env_emitter == kNoEmitter) return r;
  if (env_mapping == EnvironmentLight::Mapping::constant) return {env_scale, kInv4Pi};
  Vec3 wl = env_light_from_world.apply_vector(dir);
  float len = length(wl);
  if (!finite_positive(len)) return r;
  wl = wl / len;
  const bool equirect = env_mapping == EnvironmentLight::Mapping::equirect;
  const Vec2 uv = equirect ? lights_detail::equirect_uv(wl) : equal_area_sphere_to_square(wl);
  const int w = env_width, h = env_height;
  const int x = clamp(int(uv.x * float(w)), 0, w - 1), y = clamp(int(uv.y * float(h)), 0, h - 1);
  const EnvTexel& t = env_texels[size_t(y) * size_t(w) + size_t(x)];
  r.radiance = t.radiance;
  const float pdf_uv = t.pdf_uv;
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

RESTIR_HD inline Rgb LightsView::environment_radiance(Vec3 dir) const { return environment_lookup(dir).radiance; }

RESTIR_HD inline float LightsView::environment_pdf_unselected(Vec3 dir) const { return environment_lookup(dir).pdf; }

RESTIR_HD inline LightsView::EnvironmentValue LightsView::environment_value(Vec3 dir) const {
  if (env_emitter == kNoEmitter) return {};
  const EnvLookup look = environment_lookup(dir);
  return {look.radiance, selection.pmf(env_emitter) * look.pdf};  // point_pdf's product
}

RESTIR_HD inline float LightsView::environment_pdf(Vec3 dir) const {
  if (env_emitter == kNoEmitter) return 0;
  float pmf = selection.pmf(env_emitter);
  if (!(pmf > 0)) return 0;
  return pmf * environment_pdf_unselected(dir);
}

RESTIR_HD inline float LightsView::pdf(uint32_t emitter, Vec3 p, Vec3 light_p, Vec3 /*light_n*/) const {
  using lights_detail::finite_positive;
  if (emitter >= num_emitters) return 0;
  float pmf = selection.pmf(emitter);
  if (!(pmf > 0)) return 0;
  const LightEmitter& e = emitters[emitter];
  switch (e.kind) {
    case LightKind::point:
    case LightKind::spot:
    case LightKind::distant: return 0;  // delta lights: no other strategy produces them
    case LightKind::environment: return environment_pdf(light_p);
    case LightKind::triangle: {
      if (!(e.area > 0)) return 0;
      Vec3 d = light_p - p;
      float dist2 = length_squared(d);
      if (!finite_positive(dist2)) return 0;
      float cos_l = -dot(e.n, d) / std::sqrt(dist2);
      if (cos_l == 0 || (!e.two_sided && cos_l < 0)) return 0;
      float pdf = pmf * dist2 / (e.area * std::fabs(cos_l));
      return std::isfinite(pdf) ? pdf : 0.0f;
    }
    case LightKind::sphere: {
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

RESTIR_HD inline bool LightsView::follow(uint32_t idx, const LightsView& before, Vec3& position, Vec3& normal) const {
  if (idx >= num_emitters || idx >= before.num_emitters) return false;
  const LightEmitter &now = emitters[idx], &then = before.emitters[idx];
  if (now.kind != then.kind) return false;
  switch (now.kind) {
    case LightKind::triangle: {
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
    case LightKind::sphere:
      position = now.p0 + (position - then.p0);
      normal = normalize(position - now.p0) * (now.flip ? -1.0f : 1.0f);
      return is_finite(position);
    case LightKind::point:
    case LightKind::spot:
    case LightKind::distant:  // the one point (or direction) of a delta light is its current one
      position = now.p0;
      return true;
    case LightKind::environment:  // a direction: back into the old map's frame, out through the new one
      position = normalize(env_world_from_light.apply_vector(before.env_light_from_world.apply_vector(position)));
      return is_finite(position);
  }
  return false;
}

}  // namespace rl
