// The CUDA backend's ray queries (issue 16): the scene's BVH (backends/bvh.h), built on the host,
// lives in device memory; each batch is one kernel launch that traverses it (bvh_traverse.h, the
// code the CPU tests prove against Embree). A plain host header: no CUDA type crosses it, so the
// rest of the renderer builds with or without the CUDA toolkit.
#pragma once
#include <memory>
#include <string>

#include "backends/backend_error.h"
#include "backends/bvh_layout.h"
#include "scene/ray_queries.h"
#include "scene/scene.h"

namespace rl {

// True when this binary was built with the CUDA backend (-DRESTIR_CUDA=ON).
bool cuda_backend_built();
// Empty when a CUDA device can be used; otherwise why not (no CUDA backend in this build, no
// device, a driver older than the toolkit).
std::string cuda_unavailable_reason();
// Name and memory of device 0 ("NVIDIA H200, 139 GiB"), or the reason there is none.
std::string cuda_device_description();
// The scene's ray queries on CUDA device 0. Throws BackendError with the reason when the
// backend or a device is missing. The scene must outlive the queries (update() re-reads it).
std::unique_ptr<RayQueries> make_cuda_queries(const Scene& scene, BvhLayout layout = BvhLayout::binary);

// Traversal speed on the device alone (bench/bench_gpu.cpp): the rays are uploaded once, then
// closest-hit and any-hit kernels run `repeats` times each over the layout's tree, timed with CUDA
// events. Throws as make_cuda_queries.
struct CudaRayTiming {
  double closest_ms = 0;   // per pass over all rays, best of the repeats
  double any_ms = 0;
  double upload_ms = 0;    // rays host -> device, once
  size_t hits = 0;         // closest hits found (a check that the kernel did work)
};
CudaRayTiming cuda_time_rays(const Scene& scene, std::span<const Ray> rays, int repeats, BvhLayout layout = BvhLayout::binary);

}  // namespace rl
