// ReSTIR DI on the CUDA backend (render.backend = cuda): di_frame.h's stages run as one kernel per
// stage over device buffers, the scene, its lights and its BVH copied to the GPU once.
// A plain host header: no CUDA type crosses it.
#pragma once
#include <memory>

#include "integrators/integrator.h"

namespace rl {

// Throws std::runtime_error naming the reason when the build has no CUDA backend or no device, or
// the scene or context is one the driver does not handle yet (check_di_frame_supported).
std::unique_ptr<Integrator> make_cuda_restir_di(const RenderContext& ctx);

// The same driver on the host (HostExec: host memory, the BVH traversed on the CPU threads): the
// CUDA backend's stand-in in tests, so that CI proves its driver without a GPU. Not a user-facing
// integrator (the CPU's restir-di, on Embree, is faster). Throws as make_cuda_restir_di.
std::unique_ptr<Integrator> make_host_twin_restir_di(const RenderContext& ctx);

// Throws std::runtime_error when di_frame.h cannot render this context yet: an animated scene (its
// history needs the previous frame's lights and BVH on the device), planted biases (a CPU test harness).
void check_di_frame_supported(const RenderContext& ctx);

}  // namespace rl
