// ReSTIR DI's light candidates a batch at a time (issue 9: "cheaper candidates"). The initial
// resampling of Bitterli et al. 2020 (§3, Alg. 3) draws M = 32 light samples per pixel and
// evaluates the target at each; one at a time that is a long chain of dependent scalar work
// (cone sampling, two square roots and a division per step) and over half of a frame of many-lights.
// Here the candidates of one pixel are drawn first, then sorted by emitter kind into
// structure-of-arrays lanes, so that the compiler turns the sphere and triangle sampling, the
// geometry term and a Lambertian BSDF into SIMD loops over the candidates (RTXDI evaluates its
// candidates in the same order: draw, then evaluate). Every lane computes exactly what
// LightsView::sample_emitter, di_detail::view_light and di_value compute for one candidate -- the
// same operations in the same order, so the results are bitwise those of the scalar path (a test
// holds that); the kinds the batch does not cover (delta lights, the environment, a receiver
// inside a sphere, non-Lambertian BSDFs for the BSDF terms) fall back to those functions.
#pragma once
#include <cstdint>

#include "integrators/restir_di/di_kernel.h"

namespace rl {

inline constexpr int kDiCandidateBatch = 32;

// One batch's candidates: the inputs (emitter, its selection pmf, the point's two random numbers)
// and, after di_eval_light_candidates, the light point, its target p̂ (luminance of the
// unshadowed integrand), the light strategy's density (selection pmf x sampling density, in the
// point's area measure) and the BSDF strategy's density in the same measure.
struct DiCandidateBatch {
  int n = 0;
  uint32_t emitter[kDiCandidateBatch];
  float pmf[kDiCandidateBatch], ux[kDiCandidateBatch], uy[kDiCandidateBatch];
  float qx[kDiCandidateBatch], qy[kDiCandidateBatch], qz[kDiCandidateBatch];
  float target[kDiCandidateBatch], light_pdf[kDiCandidateBatch], bsdf_pdf[kDiCandidateBatch];
  bool valid[kDiCandidateBatch];  // a light point was sampled (else target 0 and no sample)
};

namespace di_batch_detail {

// Structure-of-arrays lanes of one emitter kind: lane k is candidate idx[k] of the batch.
struct Lanes {
  int n = 0;
  int idx[kDiCandidateBatch];
  float ox[kDiCandidateBatch], oy[kDiCandidateBatch], oz[kDiCandidateBatch];  // sphere centre / triangle p0
  float ax[kDiCandidateBatch], ay[kDiCandidateBatch], az[kDiCandidateBatch];  // triangle p1
  float bx[kDiCandidateBatch], by[kDiCandidateBatch], bz[kDiCandidateBatch];  // triangle p2
  float nx[kDiCandidateBatch], ny[kDiCandidateBatch], nz[kDiCandidateBatch];  // triangle normal
  float r[kDiCandidateBatch];      // sphere radius; triangle area
  float sign[kDiCandidateBatch];   // sphere: -1 flipped (inward normals), +1 otherwise
  float one_sided[kDiCandidateBatch];  // 1: emits on its normal's side only
  float ux[kDiCandidateBatch], uy[kDiCandidateBatch];            // the point's random numbers
  float pmf[kDiCandidateBatch];                                   // the emitter's selection pmf
  float le_r[kDiCandidateBatch], le_g[kDiCandidateBatch], le_b[kDiCandidateBatch];
};

// What sample_sphere and sample_triangle leave for the common part: the light point q, its
// normal (normal_at's), the sampling density in solid angle at the receiver (as sample_emitter
// reports it) and whether the sample exists.
struct Points {
  float qx[kDiCandidateBatch], qy[kDiCandidateBatch], qz[kDiCandidateBatch];
  float nx[kDiCandidateBatch], ny[kDiCandidateBatch], nz[kDiCandidateBatch];
  float pdf[kDiCandidateBatch];
  int32_t ok[kDiCandidateBatch];  // 0 or 1 (32-bit like the floats: the loops vectorize)
};

// Without short-circuits (&, not &&): branch-free, so that the loops below vectorize.
RESTIR_HD inline bool finite_f(float v) { return std::fabs(v) <= 3.40282347e38f; }
RESTIR_HD inline bool finite_positive_f(float v) { return (v > 0) & (v <= 3.40282347e38f); }

// LightsView::sample_sphere for a receiver outside every lane's sphere (pbrt-v4 Sphere::Sample:
// uniform in the cone subtending the sphere, PBR4 §6.2.4), then normal_at of the point.
RESTIR_HD inline void sample_spheres(const Lanes& __restrict__ l, Vec3 p, Points& __restrict__ o) {
  for (int k = 0; k < l.n; ++k) {
    const float r = l.r[k], ux = l.ux[k];
    const Vec3 c{l.ox[k], l.oy[k], l.oz[k]};
    const float dc2 = length_squared(p - c);
    const float dc = std::sqrt(dc2);
    const float sin2_max = r * r / dc2, sin_max = std::sqrt(sin2_max);
    const float cos_max = std::sqrt(std::max(1 - sin2_max, 0.0f));
    const bool small = sin2_max < 0.00068523f;  // sin^2(1.5 deg): Taylor expansion, as sample_sphere
    float cos_t = (cos_max - 1) * ux + 1;
    float sin2_t = 1 - cos_t * cos_t;
    const float sin2_small = sin2_max * ux;
    sin2_t = small ? sin2_small : sin2_t;
    cos_t = small ? std::sqrt(1 - sin2_small) : cos_t;
    const float one_minus_cos_max = small ? sin2_max / 2 : 1 - cos_max;
    const float cos_a = sin2_t / sin_max + cos_t * std::sqrt(std::max(1 - sin2_t / sin2_max, 0.0f));
    const float sin_a = std::sqrt(std::max(1 - cos_a * cos_a, 0.0f));
    float sin_phi, cos_phi;  // the cone's azimuth, 2 pi u.y
    sincos_turns(l.uy[k], sin_phi, cos_phi);
    const Frame f = Frame::from_normal((c - p) / dc);
    const Vec3 nrm = f.to_world(Vec3{-sin_a * cos_phi, -sin_a * sin_phi, -cos_a});
    const Vec3 q = c + r * nrm;
    const Vec3 d = q - c;  // normal_at(q): the radial unit vector, flipped for inward spheres
    const float len = length(d);
    const Vec3 n = d / len * l.sign[k];  // = d / -len when flipped: negation is exact
    const Vec3 to = q - p;
    const float dist2 = length_squared(to);
    const Vec3 wi = to / std::sqrt(dist2);
    const float pdf = 1 / (2 * kPi * one_minus_cos_max);
    const Vec3 n_sampled = nrm * l.sign[k];  // sample_sphere's back-side test uses nrm
    o.qx[k] = q.x, o.qy[k] = q.y, o.qz[k] = q.z;
    o.nx[k] = n.x, o.ny[k] = n.y, o.nz[k] = n.z;
    o.pdf[k] = pdf;
    o.ok[k] = (r > 0) & finite_positive_f(dist2) & !((l.one_sided[k] > 0) & (dot(n_sampled, wi) >= 0)) &
              finite_positive_f(pdf) & (len > 0);
  }
}

// LightsView::sample_triangle (uniform by area, Heitz 2019 barycentrics); its density converted to
// solid angle, d^2 / (A |cos theta_l|) (PBR4 §4.2.3), as sample_triangle reports it.
RESTIR_HD inline void sample_triangles(const Lanes& __restrict__ l, Vec3 p, Points& __restrict__ o) {
  for (int k = 0; k < l.n; ++k) {
    const float u0 = l.ux[k], u1 = l.uy[k];
    const float h0 = u0 / 2, h1 = u1 / 2;
    const float b0 = u0 < u1 ? h0 : u0 - h1;
    const float b1 = u0 < u1 ? u1 - h0 : h1;
    const float b2 = 1 - b0 - b1;
    const Vec3 q = Vec3{l.ox[k], l.oy[k], l.oz[k]} * b0 + Vec3{l.ax[k], l.ay[k], l.az[k]} * b1 +
                   Vec3{l.bx[k], l.by[k], l.bz[k]} * b2;
    const Vec3 n{l.nx[k], l.ny[k], l.nz[k]};
    const Vec3 to = q - p;
    const float dist2 = length_squared(to);
    const Vec3 wi = to / std::sqrt(dist2);
    const float cos_l = -dot(n, wi);
    const float pdf_sa = dist2 / (l.r[k] * std::fabs(cos_l));
    o.qx[k] = q.x, o.qy[k] = q.y, o.qz[k] = q.z;
    o.nx[k] = n.x, o.ny[k] = n.y, o.nz[k] = n.z;
    o.pdf[k] = pdf_sa;
    o.ok[k] = (l.r[k] > 0) & finite_positive_f(dist2) & (cos_l != 0) & !((l.one_sided[k] > 0) & (cos_l < 0)) &
              finite_positive_f(pdf_sa);
  }
}

// view_light, di_value and the two strategies' densities for every lane of one kind, written to
// the batch at the lanes' candidates. A Lambertian BSDF is evaluated in the loop
// (bsdf_detail::diffuse_eval / diffuse_pdf, the same operations); any other per lane through
// bsdf_eval / bsdf_pdf. Densities are in the light point's area measure: the sampled solid-angle
// density x g x the selection pmf (as di_initial_reservoir's scalar path), and bsdf_pdf x g.
RESTIR_HD inline void finish_lanes(const Lanes& __restrict__ l, const Points& __restrict__ o, const GSurface& s, Vec3 wo_l,
                                   bool bsdf_pdfs, DiCandidateBatch& __restrict__ b) {
  float wl_x[kDiCandidateBatch], wl_y[kDiCandidateBatch], wl_z[kDiCandidateBatch], g[kDiCandidateBatch];
  int32_t ok[kDiCandidateBatch];  // 0 or 1 (32-bit like the floats: the loops vectorize)
  const Frame shading = s.frame();
  for (int k = 0; k < l.n; ++k) {  // view_light
    const Vec3 q{o.qx[k], o.qy[k], o.qz[k]}, n{o.nx[k], o.ny[k], o.nz[k]};
    const Vec3 d = q - s.p;
    const float d2 = length_squared(d);
    const Vec3 wi = d / std::sqrt(d2);
    const bool lit = !(l.one_sided[k] > 0) | (dot(n, -wi) > 0);  // emitted(e, n, -wi)
    const Vec3 wl = shading.to_local(wi);
    wl_x[k] = wl.x, wl_y[k] = wl.y, wl_z[k] = wl.z;
    g[k] = std::fabs(dot(n, wi)) / d2;
    ok[k] = o.ok[k] & (d2 > 0) & lit;
  }
  float f_r[kDiCandidateBatch], f_g[kDiCandidateBatch], f_b[kDiCandidateBatch], pb[kDiCandidateBatch];
  if (s.bsdf.type == Material::Type::diffuse) {
    const Rgb fr = s.bsdf.reflectance * kInvPi;
    for (int k = 0; k < l.n; ++k) {
      const bool same = wo_l.z * wl_z[k] > 0;
      f_r[k] = same ? fr.x : 0.0f, f_g[k] = same ? fr.y : 0.0f, f_b[k] = same ? fr.z : 0.0f;
      pb[k] = same ? std::fabs(wl_z[k]) * kInvPi : 0.0f;
    }
  } else {
    for (int k = 0; k < l.n; ++k) {
      const Vec3 wl{wl_x[k], wl_y[k], wl_z[k]};
      const Rgb f = bsdf_eval(s.bsdf, wo_l, wl);
      f_r[k] = f.x, f_g[k] = f.y, f_b[k] = f.z;
      pb[k] = bsdf_pdfs ? bsdf_pdf(s.bsdf, wo_l, wl) : 0.0f;
    }
  }
  float t[kDiCandidateBatch], pl[kDiCandidateBatch], pbs[kDiCandidateBatch];
  for (int k = 0; k < l.n; ++k) {  // di_value, luminance, densities
    const float c = std::fabs(wl_z[k]);
    float vr = f_r[k] * c * l.le_r[k] * g[k], vg = f_g[k] * c * l.le_g[k] * g[k], vb = f_b[k] * c * l.le_b[k] * g[k];
    const bool finite = finite_f(vr) & finite_f(vg) & finite_f(vb);  // di_value: max(value, 0) when finite
    vr = finite ? std::max(vr, 0.0f) : vr, vg = finite ? std::max(vg, 0.0f) : vg, vb = finite ? std::max(vb, 0.0f) : vb;
    t[k] = ok[k] ? 0.2126f * vr + 0.7152f * vg + 0.0722f * vb : 0.0f;
    pl[k] = o.pdf[k] * l.pmf[k] * g[k];  // o.pdf: solid angle, as sample_sphere / sample_triangle report it
    pbs[k] = pb[k] * g[k];  // meaningless without bsdf_pdfs (the caller has no BSDF strategy then)
  }
  for (int k = 0; k < l.n; ++k) {  // scatter to the candidates
    const int i = l.idx[k];
    b.qx[i] = o.qx[k], b.qy[i] = o.qy[k], b.qz[i] = o.qz[k];
    b.target[i] = t[k], b.light_pdf[i] = pl[k], b.bsdf_pdf[i] = pbs[k], b.valid[i] = o.ok[k];
  }
}

}  // namespace di_batch_detail

// Evaluates the batch's sphere and triangle candidates as seen from s (wo_l: s.wo in its shading
// frame): b.valid, q, target, light_pdf and (with bsdf_pdfs) bsdf_pdf. Returns a mask of the
// candidates left to the scalar path (bit i set: delta lights, the environment, a receiver inside
// the sphere); their outputs are not written.
RESTIR_HD inline uint32_t di_eval_light_candidates(const LightsView& lights, const GSurface& s, Vec3 wo_l, bool bsdf_pdfs,
                                                   DiCandidateBatch& b) {
  using namespace di_batch_detail;
  Lanes sph, tri;
  uint32_t scalar = 0;
  for (int i = 0; i < b.n; ++i) {  // gather by kind
    const LightEmitter& e = lights.emitters[b.emitter[i]];
    const bool sphere = e.kind == LightKind::sphere && length_squared(s.p - e.p0) > e.radius * e.radius;
    if (!sphere && e.kind != LightKind::triangle) {
      scalar |= 1u << i;
      continue;
    }
    Lanes& l = sphere ? sph : tri;
    const int k = l.n++;
    l.idx[k] = i;
    l.ux[k] = b.ux[i], l.uy[k] = b.uy[i], l.pmf[k] = b.pmf[i];
    l.ox[k] = e.p0.x, l.oy[k] = e.p0.y, l.oz[k] = e.p0.z;
    l.one_sided[k] = e.two_sided ? 0.0f : 1.0f;
    l.le_r[k] = e.radiance.x, l.le_g[k] = e.radiance.y, l.le_b[k] = e.radiance.z;
    // A radius or area of 0 fails the lane: sample_emitter has no sample of a black emitter.
    if (sphere) {
      l.r[k] = is_black(e.radiance) ? 0.0f : e.radius;
      l.sign[k] = e.flip ? -1.0f : 1.0f;
    } else {
      l.r[k] = is_black(e.radiance) ? 0.0f : e.area;
      l.ax[k] = e.p1.x, l.ay[k] = e.p1.y, l.az[k] = e.p1.z;
      l.bx[k] = e.p2.x, l.by[k] = e.p2.y, l.bz[k] = e.p2.z;
      l.nx[k] = e.n.x, l.ny[k] = e.n.y, l.nz[k] = e.n.z;
    }
  }
  Points o;
  if (sph.n > 0) {
    sample_spheres(sph, s.p, o);
    finish_lanes(sph, o, s, wo_l, bsdf_pdfs, b);
  }
  if (tri.n > 0) {
    sample_triangles(tri, s.p, o);
    finish_lanes(tri, o, s, wo_l, bsdf_pdfs, b);
  }
  return scalar;
}

}  // namespace rl
