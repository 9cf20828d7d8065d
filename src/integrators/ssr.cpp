// Screen-space reflections (issue 12): the reflections real-time engines ship, as the cheap and
// biased baseline that the thesis compares ReSTIR PT against. Per pixel sample:
//   1. the G-buffer (primary hits) and the lit colour of every pixel: its emission plus direct
//      lighting, estimated as the path tracer does at depth 1 (one light sample and one BSDF
//      sample, MIS) -- what the frame shows before reflections;
//   2. surfaces whose roughness is at most ssr.roughness_cutoff take their reflected light from
//      the screen instead: ssr.rays directions drawn from the BSDF (GGX importance sampling of the
//      visible normals for glossy lobes, the mirror direction for smooth ones), each marched through
//      the depth buffer (screen_march) and weighted f |cos| / pdf; a hit returns the lit colour of
//      the pixel it lands on, a miss the environment (ssr.fallback = environment) or nothing.
// The march is the perspective-correct screen-space DDA of McGuire and Mara 2014 ("Efficient GPU
// screen-space ray tracing", JCGT 3(4)): the segment is clipped to the near plane, projected, and
// walked one pixel per step with 1/z interpolated linearly in screen space; a step whose point lies
// behind the visible surface by at most ssr.thickness (relative to that surface's distance) is a
// hit, refined by bisection.
// What it cannot show, by design (README "Screen-space reflections"): objects off screen or hidden
// from the camera, reflections of reflections (a mirror seen in a mirror shows its own lit colour),
// light arriving at glossy surfaces from emitters off screen, glass transmission (the transmitted
// direction returns the fallback), and view-dependent colour of the surface a ray lands on.
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/parallel.h"
#include "integrators/gbuffer.h"
#include "integrators/path_tracer.h"
#include "scene/bsdf.h"

namespace rl {

namespace {

struct MarchResult {
  bool hit = false;
  int x = 0, y = 0;  // the pixel the ray landed on
};

// Marches the ray (o, d) through the G-buffer of `camera` (McGuire and Mara 2014; see the file
// comment). max_distance bounds the segment (the scene's extent).
MarchResult screen_march(const PerspectiveCamera& camera, const GBuffer& g, Vec3 o, Vec3 d, float max_distance,
                         int max_steps, float thickness) {
  MarchResult r;
  const Vec3 cam = camera.position(), fwd = camera.forward();
  const float z0 = dot(o - cam, fwd);
  const float near = 1e-4f * std::max(1.0f, max_distance);
  if (!(z0 > near)) return r;
  float t1 = max_distance;
  const float dz = dot(d, fwd);
  if (dz < 0) t1 = std::min(t1, (near - z0) / dz);  // clip to the near plane
  const Vec3 e = o + d * t1;
  const float z1 = dot(e - cam, fwd);
  Vec2 s0, s1;
  camera.project(o, s0);  // raster positions, on screen or not (both points are in front)
  camera.project(e, s1);
  const float pixels = std::max(std::fabs(s1.x - s0.x), std::fabs(s1.y - s0.y));
  const int steps = std::min(max_steps, int(std::ceil(pixels)));
  if (steps < 1) return r;
  // World point at screen-space fraction a: 1/z and p/z are linear in screen space.
  auto point_at = [&](float a) {
    const float inv_z = (1 - a) / z0 + a / z1;
    return (o * ((1 - a) / z0) + e * (a / z1)) / inv_z;
  };
  // Pixel of a point and how far behind the visible surface it is (< 0: in front; NaN: no surface).
  auto probe = [&](Vec3 p, int& x, int& y) {
    Vec2 s;
    if (!camera.project(p, s)) return std::numeric_limits<float>::quiet_NaN();
    x = std::min(g.width - 1, int(s.x));
    y = std::min(g.height - 1, int(s.y));
    const GSurface& sf = g.at(x, y);
    if (!sf.valid) return -1.0f;  // background: nothing to hit there
    return length(p - cam) - sf.depth;
  };
  float a_prev = 0;
  for (int i = 1; i <= steps; ++i) {
    const float a = float(i) / float(steps);
    int x, y;
    const float behind = probe(point_at(a), x, y);
    if (std::isnan(behind)) return r;  // left the screen
    const float depth = g.at(x, y).depth;
    if (behind > 0 && behind <= thickness * depth) {
      // Bisection between the last point in front and this one, for the pixel where it crosses.
      float lo = a_prev, hi = a;
      for (int k = 0; k < 6; ++k) {
        const float mid = 0.5f * (lo + hi);
        int mx, my;
        const float b = probe(point_at(mid), mx, my);
        if (!std::isnan(b) && b > 0 && b <= thickness * g.at(mx, my).depth) {
          hi = mid;
          x = mx;
          y = my;
        } else {
          lo = mid;
        }
      }
      // The ray must arrive on the side of the surface the camera sees (its lit colour is that
      // side's); whichever way the mesh's winding points the normal.
      const GSurface& hs = g.at(x, y);
      const Vec3 seen = dot(hs.ng, hs.wo) >= 0 ? hs.ng : -hs.ng;
      if (dot(seen, d) >= 0) return r;
      r.hit = true;
      r.x = x;
      r.y = y;
      return r;
    }
    if (behind <= 0) a_prev = a;
  }
  return r;
}

class Ssr final : public Integrator {
 public:
  explicit Ssr(const RenderContext& ctx) : ctx_(ctx) {
    const Bounds3 b = ctx.scene.bounds();
    extent_ = b.empty() ? 1.0f : std::max(1e-3f, length(b.diagonal()));
  }

  void render_frame(const FrameInfo& frame, Image& out) override {
    const Options& o = ctx_.options;
    const int w = out.width, h = out.height;
    std::vector<Rgb> sum(out.size(), Rgb(0));
    PathOptions direct = o.path;
    direct.max_depth = 1;  // emission + direct light: the frame before reflections
    for (int s = 0; s < o.render.spp; ++s) {
      {
        StageTimer timer(frame.stages, "primary");
        build_gbuffer(ctx_, *frame.camera, frame.index, s, g_);
      }
      lit_.assign(out.size(), Rgb(0));
      {
        StageTimer timer(frame.stages, "direct");
        parallel_for_pixels(w, h, [&](int x, int y) {
          const uint32_t p = uint32_t(y * w + x);
          Pcg32 rng = make_rng(p, uint32_t(frame.index), RngPass::path, o.render.seed, uint32_t(s));
          lit_[p] = path_radiance(ctx_, direct, camera_ray(ctx_, *frame.camera, x, y, frame.index, s), rng);
        }, frame.progress);
      }
      StageTimer timer(frame.stages, "reflections");
      parallel_for_pixels(w, h, [&](int x, int y) {
        const uint32_t p = uint32_t(y * w + x);
        sum[p] += shade(frame, g_.at(x, y), p, s);
      });
    }
    for (size_t i = 0; i < out.size(); ++i) out.pixels[i] = sum[i] / float(o.render.spp);
  }

 private:
  // A pixel's final colour: its lit colour, or for smooth enough surfaces emission + reflections.
  Rgb shade(const FrameInfo& frame, const GSurface& sf, uint32_t p, int s) const {
    const SsrOptions& so = ctx_.options.ssr;
    if (!sf.valid || bsdf_roughness(sf.bsdf) > so.roughness_cutoff) return lit_[p];
    Pcg32 rng = make_rng(p, uint32_t(frame.index), RngPass::misc, ctx_.options.render.seed, uint32_t(s));
    const Vec3 wo_l = sf.frame.to_local(sf.wo);
    Rgb reflected(0);
    for (int i = 0; i < so.rays; ++i) {
      BsdfSample bs;
      const float u_lobe = rng.next_float();
      const Vec2 u = rng.next_2d();
      if (!bsdf_sample(sf.bsdf, wo_l, u_lobe, u, bs)) continue;
      const Rgb weight = bs.f * (std::fabs(bs.wi.z) / bs.pdf);
      const Vec3 d = sf.frame.to_world(bs.wi);
      const bool transmitted = dot(d, sf.ng) * dot(sf.wo, sf.ng) < 0;
      MarchResult m;
      if (!transmitted) {
        const Ray ray = spawn_ray(sf.p, sf.ng, d, ctx_.accel.ray_epsilon());
        m = screen_march(*frame.camera, g_, ray.o, d, extent_, so.max_steps, so.thickness);
      }
      if (m.hit)
        reflected += weight * lit_[size_t(m.y) * size_t(g_.width) + size_t(m.x)];
      else if (so.fallback == SsrFallback::environment)
        reflected += weight * ctx_.lights.environment_radiance(d);
    }
    return sf.emitted + reflected / float(so.rays);
  }

  RenderContext ctx_;
  float extent_ = 1;
  GBuffer g_;
  std::vector<Rgb> lit_;
};

}  // namespace

std::unique_ptr<Integrator> make_ssr(const RenderContext& ctx) {
  if (ctx.options.render.debug_view != DebugView::none)
    throw OptionError("render.debug_view: ssr has no debug views (they belong to the ReSTIR integrators)");
  return std::make_unique<Ssr>(ctx);
}

}  // namespace rl
