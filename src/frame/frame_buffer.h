// A frame in an integrator's own buffer, in its backend's memory (Integrator::frame_buffer): what
// the Python API hands over without a copy (DLPack; a CUDA array on the CUDA backend).
#pragma once

namespace rl {

struct FrameBuffer {
  const float* rgb = nullptr;  // height x width RGB float triples; null: none
  bool on_device = false;      // CUDA device memory (else host memory)
  int device_id = 0;
};

}  // namespace rl
