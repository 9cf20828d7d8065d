// Frames of an integrator built directly from a RenderContext (not through FrameRenderer): for
// integrators that are not in the registry, such as the CUDA ReSTIR DI's host twin.
#pragma once
#include <memory>
#include <vector>

#include "image/image.h"
#include "frame/integrator.h"

namespace rl::test {

using MakeIntegrator = std::unique_ptr<Integrator> (*)(const RenderContext&);

inline std::unique_ptr<Integrator> make_registered(const RenderContext& ctx) { return make_integrator(ctx.options.integrator, ctx); }

// `frames` frames of a static scene as FrameRenderer renders them (one camera, the previous
// frame's passed on), through the integrator `make` builds.
inline std::vector<Image> render_frames(const Scene& scene, const Options& o, MakeIntegrator make, int frames) {
  Accel accel(scene);
  Lights lights(scene, o.render.light_selection);
  const RenderContext ctx{scene, accel, lights, o};
  const auto integrator = make(ctx);
  const PerspectiveCamera camera(scene.camera.keys.empty() ? CameraKey{} : scene.camera.keys.front(), o.film.width, o.film.height);
  std::vector<Image> out;
  for (int f = 0; f < frames; ++f) {
    FrameInfo info;
    info.index = f, info.count = frames, info.camera = &camera, info.previous_camera = f > 0 ? &camera : nullptr;
    Image img(o.film.width, o.film.height);
    integrator->render_frame(info, img);
    out.push_back(std::move(img));
  }
  return out;
}

}  // namespace rl::test
