// The per-pixel stages' ray tracer on the CPU backend (frame_world.h's Tracer): Embree through
// Accel, one ray at a time. Host only.
#pragma once
#include "backends/cpu/accel.h"

namespace rl {

struct EmbreeTracer {
  const Accel* accel = nullptr;
  bool occluded(const Ray& r) const { return accel->occluded(r); }
  bool intersect(const Ray& r, Hit& hit) const { return accel->intersect(r, hit); }
};

}  // namespace rl
