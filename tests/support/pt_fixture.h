// A scene with its acceleration structure, lights and one frame's primary hits (centre of each
// pixel): what the shift-mapping tests of ReSTIR PT work on.
#pragma once
#include <memory>
#include <string>

#include "backends/cpu/embree_tracer.h"
#include "frame/gbuffer.h"
#include "frame/integrator.h"
#include "test_helpers.h"

namespace rl::test {

struct PtFixture {
  Scene scene;
  Options options;
  std::unique_ptr<Accel> accel;
  std::unique_ptr<Lights> lights;
  std::unique_ptr<RenderContext> ctx;
  GBuffer g;
  std::vector<GSurface> surfaces;  // g's pixels unpacked (what a pass reads), row by row
  explicit PtFixture(const std::string& path, int size = 24) : scene(load_scene(path)) {
    options = options_for(scene, {"render.sample_pattern=center"});
    options.film.width = options.film.height = size;
    accel = std::make_unique<Accel>(scene);
    lights = std::make_unique<Lights>(scene, LightSelection::power);
    ctx = std::make_unique<RenderContext>(RenderContext{scene, *accel, *lights, options});
    PerspectiveCamera cam(scene.camera.at_frame(0, 1), size, size);
    build_gbuffer(*ctx, cam, 0, 0, g);
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) surfaces.push_back(g.at(x, y));
  }
  // The scene as the per-pixel code reads it on the CPU backend (a static scene: no history).
  PathWorld world() const { return path_world(*ctx); }
  EmbreeTracer tracer() const { return {accel.get()}; }
  FrameWorld<EmbreeTracer> frame_world() const {
    FrameWorld<EmbreeTracer> fw;
    fw.world = world(), fw.tracer = tracer();
    return fw;
  }
  // The primary surface of a uniformly chosen pixel (may be invalid: background).
  const GSurface& random_surface(Pcg32& rng) const {
    const uint32_t size = uint32_t(g.width);
    const size_t x = rng.next_below(size);
    return surfaces[size_t(rng.next_below(size)) * size + x];
  }
  // Where one of `surfaces` is stored in the G-buffer, and the bridges' list of some of them (0 =
  // the canonical one, packed[i] for the others), as the reuse passes hand it over.
  const GPacked* packed_of(const GSurface& s) const { return &g.pixels[size_t(&s - surfaces.data())]; }
  SurfaceList surface_list(const GSurface& canonical, const GPacked* const* packed) const {
    return {&canonical, packed, g.materials.data(), g.eye};
  }
};

}  // namespace rl::test
