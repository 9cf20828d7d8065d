// The path tracer on the CUDA backend (render.backend = cuda): the scene, its lights and its BVH
// copied to the GPU once (again each frame for an animated scene), and each frame run as the CPU
// wavefront runs it -- camera rays, then per bounce: closest hits, shading (path_bounce, the same
// RESTIR_HD code as the CPU's), shadow rays, compaction of the live paths -- one kernel per stage.
// A plain host header: no CUDA type crosses it.
#pragma once
#include <memory>

#include "frame/integrator.h"

namespace rl {

// Throws std::runtime_error naming the reason when the build has no CUDA backend or no device.
std::unique_ptr<Integrator> make_cuda_path_tracer(const RenderContext& ctx);

}  // namespace rl
