// Frames as a denoiser sees them (the raw image, its AOVs, A-SVGF's re-shaded previous frame), and
// a bit-exact comparison of two images: shared by the SVGF stage tests on the host
// (tests/post/test_svgf_stages.cpp) and on the device (tests/gpu/test_gpu_svgf.cpp).
#pragma once
#include <doctest/doctest.h>

#include <cstring>
#include <functional>
#include <vector>

#include "frame/render.h"
#include "image/image.h"

namespace rl::test {

// One frame as a denoiser sees it.
struct DenoiserInput {
  Image raw, reshaded;
  Aovs aovs;
};

// The frames of `scene` under `o` (its integrator), the camera at camera(f) in frame f.
inline std::vector<DenoiserInput> render_denoiser_inputs(const Scene& scene, const Options& o, int frames,
                                                         const std::function<CameraKey(int)>& camera) {
  FrameRenderer r(scene, o);
  r.request_aovs(true);
  std::vector<DenoiserInput> out;
  for (int f = 0; f < frames; ++f) {
    DenoiserInput in;
    r.render_frame(camera(f), frames, in.raw, nullptr);
    in.aovs = r.aovs();
    in.reshaded = r.reshaded();
    out.push_back(std::move(in));
  }
  return out;
}

// How many of the two images' floats (3 a pixel) differ in any bit.
inline size_t differing_floats(const Image& a, const Image& b) {
  REQUIRE(a.width == b.width);
  REQUIRE(a.height == b.height);
  size_t n = 0;
  for (size_t i = 0; i < a.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const float x = a.pixels[i][c], y = b.pixels[i][c];
      n += std::memcmp(&x, &y, sizeof(float)) != 0;
    }
  return n;
}

}  // namespace rl::test
