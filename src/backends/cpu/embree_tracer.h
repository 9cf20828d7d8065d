// The per-pixel stages' ray tracer on the CPU backend (frame_world.h's Tracer): Embree through
// Accel, one ray at a time, each query counted in `rays` while the frame counts them
// (core/ray_counter.h). Host only.
#pragma once
#include "backends/cpu/accel.h"
#include "core/ray_counter.h"

namespace rl {

struct EmbreeTracer {
  const Accel* accel = nullptr;
  RayCounter rays{};
  bool occluded(const Ray& r) const {
    rays.add(true);
    return accel->occluded(r);
  }
  bool intersect(const Ray& r, Hit& hit) const {
    rays.add(false);
    return accel->intersect(r, hit);
  }
};

}  // namespace rl
