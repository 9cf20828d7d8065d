// Shared by the benchmarks.
#pragma once
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <mutex>
#include <string>
#include <vector>

#include "core/parallel.h"
#include "frame/render.h"
#include "integrators/path/path_tracer.h"
#include "frame/stage_times.h"
#include "backends/cpu/accel.h"

namespace rl::bench {

// Median of the values after the first `skip` (e.g. a warm-up frame or one without history).
inline double median(std::vector<double> v, size_t skip = 0) {
  if (v.size() > skip) v.erase(v.begin(), v.begin() + long(skip));
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

// "stage a.b ms, stage c.d ms, ...": the median of each stage over the frames after `skip`.
inline std::string stage_summary(const std::vector<StageTimes>& frames, size_t skip = 0) {
  std::string out;
  for (const std::string& name : stage_names(frames)) {
    std::vector<double> v;
    for (const StageTimes& f : frames) v.push_back(f.of(name));
    out += fmt::format("{}{} {:.1f} ms", out.empty() ? "" : ", ", name, median(v, skip));
  }
  return out;
}

// "stage c+a, ...; frame C closest + A any": the median rays per pixel (closest-hit + any-hit) of
// each stage that traced rays, over the frames after `skip` (core/ray_counter.h).
inline std::string ray_summary(const std::vector<StageTimes>& frames, double pixels, size_t skip = 0) {
  std::string out;
  const auto per_px = [&](const auto& value) {
    std::vector<double> v;
    for (const StageTimes& f : frames) v.push_back(double(value(f)) / pixels);
    return median(v, skip);
  };
  for (const std::string& name : ray_stage_names(frames))
    out += fmt::format("{}{} {:.2f}+{:.2f}", out.empty() ? "" : ", ", name,
                       per_px([&](const StageTimes& f) { return f.rays_of(name).closest; }),
                       per_px([&](const StageTimes& f) { return f.rays_of(name).any; }));
  out += fmt::format("; frame {:.2f} closest + {:.2f} any per pixel", per_px([](const StageTimes& f) { return f.total_rays().closest; }),
                     per_px([](const StageTimes& f) { return f.total_rays().any; }));
  return out;
}

// Seconds Embree alone takes to answer `rays` (closest hit) and `shadow` (any hit) with the
// scalar queries the renderer issues, over all cores in chunks of 4096 rays: the rays' own cost.
inline double replay(const Accel& accel, const std::vector<Ray>& rays, const std::vector<Ray>& shadow) {
  const int chunk = 4096;
  const int n1 = int((rays.size() + chunk - 1) / chunk), n2 = int((shadow.size() + chunk - 1) / chunk);
  const auto t0 = std::chrono::steady_clock::now();
  parallel_for(n1 + n2, [&](int c) {
    if (c < n1) {
      const size_t end = std::min(rays.size(), size_t(c + 1) * chunk);
      for (size_t i = size_t(c) * chunk; i < end; ++i) {
        Hit h;
        (void)accel.intersect(rays[i], h);
      }
    } else {
      const size_t b = size_t(c - n1) * chunk, end = std::min(shadow.size(), b + chunk);
      for (size_t i = b; i < end; ++i) (void)accel.occluded(shadow[i]);
    }
  });
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// A frame against its own rays: `frames` frames (history), then one frame whose rays are logged
// and replayed through Embree alone (median of three replays).
struct RayShare {
  double frame_ms = 0;   // median of the history frames after the first
  double embree_ms = 0;  // Embree alone on the logged frame's rays
  double closest_per_pixel = 0, any_hit_per_pixel = 0;
};
inline RayShare ray_share(const Scene& scene, const Options& o, int frames) {
  Camera camera = scene.camera;
  if (camera.keys.empty()) camera.keys.push_back(CameraKey{});
  FrameRenderer renderer(scene, o);
  Image img(o.film.width, o.film.height);
  std::vector<double> ms;
  const int count = frames + 1;
  for (int f = 0; f < frames; ++f) ms.push_back(renderer.render_frame(camera.at_frame(f, count), count, img, nullptr));
  RayLog log;
  renderer.set_ray_log(&log);
  (void)renderer.render_frame(camera.at_frame(frames, count), count, img, nullptr);
  renderer.set_ray_log(nullptr);
  const std::vector<Ray> closest = log.closest(), any_hit = log.any_hit();
  const Accel accel(scene);
  std::vector<double> embree_ms;
  for (int k = 0; k < 3; ++k) embree_ms.push_back(1000 * replay(accel, closest, any_hit));
  const double pixels = double(o.film.width) * o.film.height * o.render.spp;
  return {median(ms, ms.size() > 1 ? 1 : 0), median(embree_ms), double(closest.size()) / pixels,
          double(any_hit.size()) / pixels};
}
inline void print_ray_share(const std::string& what, const RayShare& r) {
  fmt::print("rays of one {} frame: {:.2f} closest-hit + {:.2f} any-hit per pixel sample; Embree alone replays them in "
             "{:.1f} ms = {:.0f}% of the {:.1f} ms frame ({:.1f} ms outside the rays)\n",
             what, r.closest_per_pixel, r.any_hit_per_pixel, r.embree_ms, 100 * r.embree_ms / r.frame_ms, r.frame_ms,
             r.frame_ms - r.embree_ms);
}

// Scenes from small to large (bench_scaling, bench_bvh): the Cornell box (30 triangles), the
// teapots, many-lights (spheres, 2400 emitters) and the 1.09 M-triangle, 10,000-emitter teapot field.
inline std::vector<std::string> scenes_by_size() {
  return {std::string(RESTIR_SHARED_DIR) + "/scenes/cornell-box/scene-v4.pbrt", std::string(RESTIR_SOURCE_DIR) + "/scenes/teapot.pbrt",
          std::string(RESTIR_SOURCE_DIR) + "/scenes/many-lights.pbrt", std::string(RESTIR_SOURCE_DIR) + "/scenes/teapot-field.pbrt"};
}

// Every ray one frame of the reference path tracer traces (closest-hit rays, shadow rays).
inline void record_rays(const RenderContext& ctx, const PerspectiveCamera& cam, std::vector<Ray>& rays, std::vector<Ray>& shadow) {
  const Options& o = ctx.options;
  std::mutex m;
  parallel_for(o.film.height, [&](int y) {
    PathStats st;
    std::vector<Ray> r, s;
    st.record_rays = &r;
    st.record_shadow_rays = &s;
    for (int x = 0; x < o.film.width; ++x)
      for (int k = 0; k < o.render.spp; ++k) {
        Pcg32 rng = make_rng(uint32_t(y * o.film.width + x), 0, RngPass::path, o.render.seed, uint32_t(k));
        (void)path_radiance(ctx, o.path, camera_ray(camera_sampling(ctx.options), cam, x, y, 0, k), rng, &st);
      }
    std::lock_guard lock(m);
    rays.insert(rays.end(), r.begin(), r.end());
    shadow.insert(shadow.end(), s.begin(), s.end());
  });
}

}  // namespace rl::bench
