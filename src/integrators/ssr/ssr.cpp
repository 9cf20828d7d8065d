// Screen-space reflections (issue 12): the reflections real-time engines ship, as the cheap and
// biased baseline that the thesis compares ReSTIR PT against. Per pixel sample:
//   1. the G-buffer (primary hits) and the lit colour of every pixel: its emission plus direct
//      lighting, estimated as the path tracer does at depth 1 (one light sample and one BSDF
//      sample, MIS) -- what the frame shows before reflections;
//   2. surfaces whose roughness is at most ssr.roughness_cutoff take their reflected light from
//      the screen instead: ssr.rays directions drawn from the BSDF (GGX importance sampling of the
//      visible normals for glossy lobes, the mirror direction for smooth ones), each marched through
//      the depth buffer (march_hiz / march_linear) and weighted f |cos| / pdf; a hit returns the lit colour of
//      the pixel it lands on, a miss the environment (ssr.fallback = environment) or nothing.
//   3. the resolve (Stachowiak 2015, "Stochastic screen-space reflections", SIGGRAPH Advances in
//      Real-Time Rendering): a glossy pixel also reuses the rays its neighbours traced, each
//      weighted by this pixel's BRDF x cosine over the pdf it was drawn with, normalised by the sum
//      of the weights and scaled by this pixel's directional albedo (its own rays' mean f cos/pdf):
//      a ratio estimator -- much less noise, slightly biased, as in the engines;
//   4. optionally (ssr.temporal), the reflective pixels blend with the previous frame's, reprojected.
// The march (ssr_march.h) walks a hierarchical depth buffer (Hi-Z) or, for comparison, every pixel.
// The primary hits are traced once: the lit colour continues the G-buffer's paths.
// What it cannot show, by design (README "Screen-space reflections"): objects off screen or hidden
// from the camera, reflections of reflections (a mirror seen in a mirror shows its own lit colour),
// light arriving at glossy surfaces from emitters off screen, glass transmission (the transmitted
// direction returns the fallback), and view-dependent colour of the surface a ray lands on. A
// smooth-coated diffuse surface counts as rough (bsdf_roughness: its non-delta lobe is the base),
// so its coat mirrors emitters (the lit colour's BSDF sample) but not the screen.
#include <algorithm>
#include <cmath>
#include <span>

#include "core/parallel.h"
#include "core/sampling.h"
#include "frame/gbuffer.h"
#include "integrators/path/path_tracer.h"
#include "integrators/ssr/ssr_march.h"
#include "scene/bsdf.h"

namespace rl {

namespace {

// One reflection ray a pixel traced, kept for the resolve of its neighbours.
struct ReflectionRay {
  bool valid = false;  // a direction was drawn
  bool hit = false;    // it landed on a pixel (else: fallback)
  Vec3 dir;            // world direction
  Vec3 hit_p;          // the surface point it landed on
  Rgb radiance{0};     // what it returned: the landed pixel's lit colour, the fallback or nothing
  Rgb weight{0};       // f |cos| / pdf at the pixel that traced it
  float pdf = 0;       // solid-angle pdf of dir (0: a delta lobe)
};

// Neighbours a pixel may reuse rays from in the resolve: similar surfaces only, so that rays do
// not leak across silhouettes (the thresholds of the ReSTIR integrators' defaults).
constexpr float kResolveDepth = 0.1f, kResolveNormalDeg = 25.0f;

class Ssr final : public Integrator {
 public:
  explicit Ssr(const RenderContext& ctx) : ctx_(ctx) {
    const Bounds3 b = ctx.scene.bounds();
    extent_ = b.empty() ? 1.0f : std::max(1e-3f, length(b.diagonal()));
  }

  void render_frame(const FrameInfo& frame, Image& out) override {
    const Options& o = ctx_.options;
    sum_.assign(out.size(), Rgb(0));
    for (int s = 0; s < o.render.spp; ++s) {
      primary(frame, s);
      direct(frame, s);
      reflections(frame, s);
      resolve(frame, s);
    }
    for (size_t i = 0; i < out.size(); ++i) out.pixels[i] = sum_[i] / float(o.render.spp);
    if (o.ssr.temporal) temporal(frame, out);
  }

 private:
  bool reflective(const GSurface& sf) const {
    return sf.valid && bsdf_roughness(sf.bsdf) <= ctx_.options.ssr.roughness_cutoff;
  }

  // Primary rays (one batched query per row) and the G-buffer and Hi-Z pyramid built from them.
  void primary(const FrameInfo& frame, int s) {
    StageTimer timer(frame.stages, "primary");
    const int w = frame.camera->width(), h = frame.camera->height();
    rays_.resize(size_t(w) * size_t(h));
    hits_.resize(rays_.size());
    const std::vector<Mat4> back = motion_back(ctx_.scene, frame.index);  // motion vectors (temporal)
    g_.resize(w, h, !back.empty());
    const CameraSampling cs = camera_sampling(ctx_.options);
    const SceneView& scene = ctx_.accel.scene_view();
    const LightsView& lights = ctx_.lights.view();
    parallel_for(h, [&](int y) {
      const size_t row = size_t(y) * size_t(w);
      for (int x = 0; x < w; ++x) rays_[row + size_t(x)] = camera_ray(cs, *frame.camera, x, y, frame.index, s);
      const auto rays = std::span<const Ray>(rays_).subspan(row, size_t(w));
      ctx_.accel.intersect(rays, std::span(hits_).subspan(row, size_t(w)), true);
      for (size_t i = row; i < row + size_t(w); ++i)
        fill_gsurface(scene, lights, rays_[i], hits_[i].valid() ? &hits_[i] : nullptr, g_.pixels[i], back.data(), uint32_t(back.size()),
                      g_.motion_slot(i));
    });
    hiz_.build(*frame.camera, g_);
  }

  // Lit colour: emission + direct light, the path tracer at depth 1 continuing the primary hits
  // (the same random numbers as path_radiance on the same camera ray: the same colour).
  void direct(const FrameInfo& frame, int s) {
    StageTimer timer(frame.stages, "direct");
    const Options& o = ctx_.options;
    PathOptions depth1 = o.path;
    depth1.max_depth = 1;
    lit_.resize(rays_.size());
    parallel_for_pixels(g_.width, g_.height, [&](int x, int y) {
      const uint32_t p = uint32_t(y * g_.width + x);
      Pcg32 rng = make_rng(p, uint32_t(frame.index), RngPass::path, o.render.seed, uint32_t(s));
      lit_[p] = path_radiance_from_hit(ctx_, depth1, rays_[p], hits_[p].valid() ? &hits_[p] : nullptr, rng);
    }, frame.progress);
  }

  // ssr.rays BSDF-sampled rays per reflective pixel, marched through the screen.
  void reflections(const FrameInfo& frame, int s) {
    StageTimer timer(frame.stages, "reflections");
    const SsrOptions& so = ctx_.options.ssr;
    const size_t rays = size_t(so.rays);
    traced_.assign(g_.pixels.size() * rays, ReflectionRay{});
    parallel_for_pixels(g_.width, g_.height, [&](int x, int y) {
      const uint32_t p = uint32_t(y * g_.width + x);
      const GSurface& sf = g_.pixels[p];
      if (!reflective(sf)) return;
      Pcg32 rng = make_rng(p, uint32_t(frame.index), RngPass::misc, ctx_.options.render.seed, uint32_t(s));
      for (size_t i = 0; i < rays; ++i) traced_[p * rays + i] = trace(*frame.camera, sf, rng);
    });
  }

  ReflectionRay trace(const PerspectiveCamera& camera, const GSurface& sf, Pcg32& rng) const {
    const SsrOptions& so = ctx_.options.ssr;
    ReflectionRay r;
    BsdfSample bs;
    const float u_lobe = rng.next_float();
    const Vec2 u = rng.next_2d();
    const Frame shading = sf.frame();
    if (!bsdf_sample(sf.bsdf, shading.to_local(sf.wo), u_lobe, u, bs) || !(bs.pdf > 0)) return r;
    r.valid = true;
    r.weight = bs.f * (std::fabs(bs.wi.z) / bs.pdf);
    r.pdf = bs.is_delta ? 0.0f : bs.pdf;
    r.dir = shading.to_world(bs.wi);
    // A transmitted direction sees nothing the screen shows (glass): the fallback.
    if (dot(r.dir, sf.ng) * dot(sf.wo, sf.ng) >= 0) {
      const Ray ray = spawn_ray(sf.p, sf.ng, r.dir, ctx_.accel.ray_epsilon());
      const MarchResult m = so.hi_z ? march_hiz(camera, g_, hiz_, ray.o, r.dir, extent_, so.max_steps, so.thickness)
                                    : march_linear(camera, g_, hiz_, ray.o, r.dir, extent_, so.max_steps, so.thickness);
      if (m.hit) {
        const size_t q = size_t(m.y) * size_t(g_.width) + size_t(m.x);
        r.hit = true;
        r.hit_p = g_.pixels[q].p;
        r.radiance = lit_[q];
        return r;
      }
    }
    if (so.fallback == SsrFallback::environment) r.radiance = ctx_.lights.environment_radiance(r.dir);
    return r;
  }

  // Each pixel's colour for this sample, added to sum_.
  void resolve(const FrameInfo& frame, int s) {
    StageTimer timer(frame.stages, "resolve");
    parallel_for_pixels(g_.width, g_.height, [&](int x, int y) {
      const uint32_t p = uint32_t(y * g_.width + x);
      const GSurface& sf = g_.pixels[p];
      sum_[p] += reflective(sf) ? sf.le + reflected(frame, s, x, y) : lit_[p];
    });
  }

  // Reflected radiance at pixel (x, y): the mean of its own rays' f cos/pdf x L, or with the
  // resolve, Stachowiak's ratio estimator over its own and its neighbours' rays (file comment).
  Rgb reflected(const FrameInfo& frame, int s, int x, int y) const {
    const SsrOptions& so = ctx_.options.ssr;
    const size_t rays = size_t(so.rays), p = size_t(y) * size_t(g_.width) + size_t(x);
    const GSurface& sf = g_.pixels[p];
    Rgb own(0), albedo(0);
    for (size_t i = 0; i < rays; ++i) {
      const ReflectionRay& r = traced_[p * rays + i];
      own += r.weight * r.radiance;
      albedo += r.weight;
    }
    own /= float(rays);
    albedo /= float(rays);
    if (so.resolve_neighbors == 0 || bsdf_is_delta(sf.bsdf)) return own;
    const Frame shading = sf.frame();
    const Vec3 wo = shading.to_local(sf.wo);
    Rgb num(0);
    float den = 0;
    auto reuse = [&](const ReflectionRay& r) {  // weight: this pixel's BRDF x cos over r's pdf
      if (!r.valid || !(r.pdf > 0)) return;
      const Vec3 d = r.hit ? normalize(r.hit_p - sf.p) : r.dir;
      const Vec3 wi = shading.to_local(d);
      const float wgt = luminance(bsdf_eval(sf.bsdf, wo, wi)) * std::fabs(wi.z) / r.pdf;
      if (!(wgt > 0) || !std::isfinite(wgt)) return;
      num += r.radiance * wgt;
      den += wgt;
    };
    for (size_t i = 0; i < rays; ++i) reuse(traced_[p * rays + i]);
    // The neighbourhood shrinks with the lobe (Stachowiak 2015 scales the resolve kernel with the
    // BRDF's footprint): a near-mirror's neighbours' rays point outside its lobe and only add noise.
    const float radius = so.resolve_radius * std::min(1.0f, bsdf_roughness(sf.bsdf) / std::max(so.roughness_cutoff, 1e-3f));
    Pcg32 rng = make_rng(uint32_t(p), uint32_t(frame.index), RngPass::spatial, ctx_.options.render.seed, uint32_t(s));
    for (int k = 0; k < so.resolve_neighbors && radius >= 0.5f; ++k) {
      const Vec2 d = sample_uniform_disk_concentric(rng.next_2d()) * radius;
      const int nx = x + int(std::lround(d.x)), ny = y + int(std::lround(d.y));
      if ((nx == x && ny == y) || nx < 0 || ny < 0 || nx >= g_.width || ny >= g_.height) continue;
      const size_t q = size_t(ny) * size_t(g_.width) + size_t(nx);
      if (!similar_surfaces(sf, g_.pixels[q], kResolveDepth, kResolveNormalDeg)) continue;
      for (size_t i = 0; i < rays; ++i) reuse(traced_[q * rays + i]);
    }
    return den > 0 ? albedo * (num / den) : own;
  }

  // ssr.temporal: blend the reflective pixels with the previous frame's where the reprojected
  // surface is the same (depth and normal) and the history's colour is within this frame's
  // neighbourhood range, then keep this frame as the history.
  void temporal(const FrameInfo& frame, Image& out) {
    StageTimer timer(frame.stages, "temporal");
    const float alpha = ctx_.options.ssr.temporal_alpha;
    current_ = out.pixels;
    if (frame.previous_camera && history_.size() == out.size()) {
      parallel_for_pixels(g_.width, g_.height, [&](int x, int y) {
        const size_t p = size_t(y) * size_t(g_.width) + size_t(x);
        const GSurface& sf = g_.pixels[p];
        if (!reflective(sf)) return;
        // Where the previous frame showed this reflection: a reflection moves with its virtual
        // image -- the reflected point seen through the surface, the view ray extended by the
        // rays' hit distance -- not with the surface (parallax-corrected reprojection, as in
        // Stachowiak 2015). The reflector must be the same surface there (normals agree, and it
        // lies on this one's tangent plane).
        // Through the pixel's centre, not its jittered sample, so that a still camera finds the
        // same pixel and a moving one filters the same way whatever the jitter.
        const Vec3 cam = frame.camera->position();
        const Vec3 view = frame.camera->generate_ray({float(x) + 0.5f, float(y) + 0.5f}).d;
        const Vec3 virtual_point = cam + view * (length(sf.p - cam) + reflection_distance(p));
        const GMotion motion = g_.motion_at(x, y);
        const Vec3 moved = motion.p_previous + (virtual_point - sf.p);  // with the reflector's own motion
        // The history there, filtered bilinearly over the previous pixels that show this reflector
        // (a nearest-pixel fetch under motion aliases: its choice of pixel jumps with the jitter).
        Vec2 r;
        if (!frame.previous_camera->project(moved, r)) return;
        const float fx = r.x - 0.5f, fy = r.y - 0.5f;
        const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
        Rgb history(0);
        float weight = 0;
        for (int k = 0; k < 4; ++k) {
          const int hx = x0 + (k & 1), hy = y0 + (k >> 1);
          if (hx < 0 || hy < 0 || hx >= g_.width || hy >= g_.height) continue;
          const size_t q = size_t(hy) * size_t(g_.width) + size_t(hx);
          const GSurface& before = previous_g_.pixels[q];
          if (!reflective(before) || dot(before.ns, motion.ns_previous) < std::cos(kResolveNormalDeg * kPi / 180.0f) ||
              std::fabs(dot(before.p - motion.p_previous, motion.ns_previous)) > 0.02f * before.depth)  // on this reflector's plane
            continue;
          const float w = ((k & 1) ? fx - float(x0) : 1 - (fx - float(x0))) * ((k >> 1) ? fy - float(y0) : 1 - (fy - float(y0)));
          history += history_[q] * w;
          weight += w;
        }
        if (!(weight > 1e-3f)) return;
        history /= weight;
        // Neighbourhood clamping (Karis 2014, "High-quality temporal supersampling"): the history
        // is clamped to the colour range of this frame's 3x3 neighbourhood, so that what the
        // reflection showed a frame ago (before the view or the objects moved) cannot linger.
        Rgb lo(kInfinity), hi(-kInfinity);
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int nx = std::clamp(x + dx, 0, g_.width - 1), ny = std::clamp(y + dy, 0, g_.height - 1);
            const Rgb c = current_[size_t(ny) * size_t(g_.width) + size_t(nx)];
            lo = min(lo, c);
            hi = max(hi, c);
          }
        const Rgb h = max(lo, min(hi, history));
        out.pixels[p] = h + (current_[p] - h) * alpha;
      });
    }
    history_ = out.pixels;
    previous_g_ = g_;
  }

  // Mean distance from pixel p's surface to where its reflection rays landed (the scene's extent
  // when none landed: the reflection of something far away, e.g. the sky).
  float reflection_distance(size_t p) const {
    const size_t rays = size_t(ctx_.options.ssr.rays);
    const Vec3 at = g_.pixels[p].p;
    float sum = 0;
    int n = 0;
    for (size_t i = 0; i < rays; ++i)
      if (traced_[p * rays + i].hit) sum += length(traced_[p * rays + i].hit_p - at), ++n;
    return n > 0 ? sum / float(n) : extent_;
  }

  RenderContext ctx_;
  float extent_ = 1;
  // Buffers, allocated once per frame size and reused by every sample and frame.
  std::vector<Ray> rays_;
  std::vector<Hit> hits_;
  GBuffer g_, previous_g_;
  HiZPyramid hiz_;
  std::vector<Rgb> lit_, sum_, history_, current_;
  std::vector<ReflectionRay> traced_;
};

}  // namespace

void check_ssr(const RenderContext& ctx) { refuse_debug_views(ctx, "ssr has no debug views (they belong to the ReSTIR integrators)"); }

std::unique_ptr<Integrator> make_ssr(const RenderContext& ctx) { return std::make_unique<Ssr>(ctx); }

}  // namespace rl
