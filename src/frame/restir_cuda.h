// ReSTIR DI, GI and PT on the CUDA backend (render.backend = cuda): di_frame.h's, gi_frame.h's and
// pt_frame.h's stages run as one kernel per stage over device buffers, the scene, its lights and
// its BVH copied to the GPU once (twice with pt.direct = restir-di: the DI driver keeps its own copy).
// A plain host header: no CUDA type crosses it.
#pragma once
#include <memory>

#include "frame/integrator.h"

namespace rl {

// Throw std::runtime_error naming the reason when the build has no CUDA backend or no device, or
// the scene or context is one the drivers do not handle yet (check_frame_supported, reuse_frame.h).
std::unique_ptr<Integrator> make_cuda_restir_di(const RenderContext& ctx);
std::unique_ptr<Integrator> make_cuda_restir_gi(const RenderContext& ctx);
std::unique_ptr<Integrator> make_cuda_restir_pt(const RenderContext& ctx);

// The same drivers on the host (HostExec: host memory, the BVH traversed on the CPU threads): the
// CUDA backend's stand-ins in tests, so that CI proves its drivers without a GPU. Not user-facing
// integrators (the CPU's, on Embree, are faster). Throw as the CUDA ones.
std::unique_ptr<Integrator> make_host_twin_restir_di(const RenderContext& ctx);
std::unique_ptr<Integrator> make_host_twin_restir_gi(const RenderContext& ctx);
std::unique_ptr<Integrator> make_host_twin_restir_pt(const RenderContext& ctx);

}  // namespace rl
