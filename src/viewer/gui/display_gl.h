// The live display transform on the GPU: the HDR frame goes up as a float texture and a fragment
// shader applies exposure, the tone mapper and the sRGB curve into the texture the window shows.
// On a CPU-bound renderer this keeps the per-frame display cost off the render threads. The
// shader mirrors image/tonemap.cpp (tonemap_pixel), which stays the one definition: screenshots
// and every saved PNG go through it, and each script screenshot checks that the shader's image
// agrees with it (GlDisplay::max_difference, written to the sidecar).
#pragma once
#include "image/image.h"
#include "image/tonemap_options.h"

namespace rl::viewer {

class GlDisplay {
 public:
  GlDisplay() = default;
  ~GlDisplay();
  GlDisplay(const GlDisplay&) = delete;
  GlDisplay& operator=(const GlDisplay&) = delete;

  // Compiles the shader and makes the textures; false (with a warning) when the context cannot,
  // and then show_ldr() alone is used. Call with the window's context current.
  bool init();
  bool gpu() const { return program_ != 0; }
  // Tone maps `hdr` on the GPU into texture().
  void show_hdr(const Image& hdr, const OutputOptions& o);
  // Shows an image already display-ready ([0,1], sRGB when wanted): the error map, the split view,
  // and every view when the GPU path is unavailable.
  void show_ldr(const Image& ldr);
  unsigned texture() const { return output_; }
  int width() const { return width_; }
  int height() const { return height_; }
  // The largest per-channel difference between texture() and `ldr` (both 8-bit), in units of 1/255.
  int max_difference(const Image& ldr) const;

 private:
  void resize(int w, int h);
  unsigned program_ = 0, vao_ = 0, fbo_ = 0, hdr_ = 0, output_ = 0;
  int width_ = 0, height_ = 0;
};

}  // namespace rl::viewer
