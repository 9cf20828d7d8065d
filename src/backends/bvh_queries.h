// RayQueries answered by the CUDA backend's own BVH (bvh.h) traversed on the CPU threads: the
// host twin of the GPU traversal, so that CI (no GPU) proves the traversal code against Embree
// and renders with it. Not a user-facing backend: Embree is faster on the CPU.
#pragma once
#include "backends/bvh.h"
#include "scene/ray_queries.h"

namespace rl {

class BvhQueries final : public RayQueries {
 public:
  explicit BvhQueries(const Scene& scene, BvhLayout layout = BvhLayout::binary) : scene_(scene), layout_(layout), bvh_(build_bvh(scene, layout)) {}
  void intersect_batch(std::span<const Ray> rays, std::span<Hit> hits, bool coherent = false) const override;
  void occluded_batch(std::span<const Ray> rays, std::span<uint8_t> blocked) const override;
  void update() override { bvh_ = build_bvh(scene_, layout_); }
  const char* backend_name() const override { return "cpu-bvh"; }
  const Bvh& bvh() const { return bvh_; }

 private:
  const Scene& scene_;
  BvhLayout layout_;
  Bvh bvh_;
};

}  // namespace rl
