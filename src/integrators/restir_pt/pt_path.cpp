#include "integrators/restir_pt/pt_path.h"

#include <cstdio>
#include <string>

#include "backends/cpu/embree_tracer.h"
#include "core/widest.h"
#include "integrators/restir_pt/restir_pt_pixel.h"

namespace rl {

PathSettings path_settings(const Options& o) {
  PathSettings ps;
  ps.path = o.path;
  ps.pt = o.pt;
  ps.min_length = o.pt.direct == DirectLighting::restir_di ? 3 : 2;
  return ps;
}

// The initial paths and the shifts on the host's widest instruction set (core/widest.h): ReSTIR PT's
// candidate stage took 20% less time, its spatial pass 18% less (teapots, 640x360, 6 paired runs).
RL_WIDEST PathReservoir initial_path_reservoir(const PathWorld& world, const EmbreeTracer& tracer, const PathSettings& ps,
                                               const GSurface& s, uint64_t seed, int candidates, const LightTileView& tile) {
  return initial_path_reservoir<EmbreeTracer>(world, tracer, ps, s, seed, candidates, tile);
}

RL_WIDEST bool shift_path(const PathWorld& world, const EmbreeTracer& tracer, const PathSettings& ps, const PathSample& base,
                          const GSurface& y1, PathSample& out, float& jacobian) {
  return shift_path<EmbreeTracer>(world, tracer, ps, base, y1, out, jacobian);
}

std::vector<PathSample> walk_paths(const PathWorld& world, const EmbreeTracer& tracer, const PathSettings& ps, const GSurface& s,
                                   uint64_t walk_seed) {
  std::vector<PathSample> out;
  if (!s.valid || world.lights.empty()) return out;
  pt_detail::Walk w;
  pt_detail::walk_from(world, tracer, ps, s, walk_seed, w,
                       [&](const pt_detail::OfferedPath& o) { out.push_back(pt_detail::describe_offered(ps, w, o, walk_seed)); });
  return out;
}

void add_direct_light(Integrator& direct, const FrameInfo& frame, Image& out, bool rerender) {
  Image di(out.width, out.height);
  FrameInfo di_frame = frame;
  StageTimes di_stages;
  di_frame.stages = &di_stages;
  if (rerender) direct.rerender_previous(di_frame, di);
  else direct.render_frame(di_frame, di);
  if (frame.stages) {
    for (const auto& [name, ms] : di_stages.ms) frame.stages->add("di." + name, ms);
    for (const auto& [name, rays] : di_stages.rays) frame.stages->add_rays("di." + name, rays);
  }
  for (size_t i = 0; i < out.size(); ++i) out.pixels[i] += di.pixels[i];
}

void print_reconnection_histogram(int frame, int chain, std::span<const PathReservoir> reservoirs) {
  std::vector<size_t> count;
  for (const PathReservoir& r : reservoirs) {
    const size_t k = r.has_sample() ? size_t(r.sample.rc) : 0;
    if (count.size() <= k) count.resize(k + 1, 0);
    ++count[k];
  }
  std::string line = "restir-pt frame " + std::to_string(frame) + " chain " + std::to_string(chain) + ": reconnection depth histogram";
  for (size_t k = 0; k < count.size(); ++k)
    if (count[k]) line += " k=" + std::to_string(k) + ":" + std::to_string(count[k]);
  std::fprintf(stderr, "%s\n", line.c_str());
}

}  // namespace rl
