// The public entry point: render a scene with options into HDR frames. The CLI and the study
// harness drive integrators only through this.
#pragma once
#include <functional>
#include <vector>

#include "image/image.h"
#include "integrators/options.h"
#include "integrators/planted_bias.h"
#include "integrators/stage_times.h"
#include "scene/scene.h"

namespace rl {

struct RenderResult {
  Image last;                    // the last frame of the sequence
  Image average;                 // mean of all frames (converges for static scenes)
  std::vector<double> frame_ms;  // wall time of each frame
  std::vector<StageTimes> frame_stages;  // wall time of each frame's stages (stage_times.h)
};

struct RenderHooks {
  // Called after each frame with its image and wall time.
  std::function<void(int frame, const Image& image, double ms)> on_frame;
  bool progress_bar = false;     // draw a progress bar on stderr
  const PlantedBias* planted = nullptr;  // tests only (planted_bias.h)
};

// Applies what the scene file says (Film resolution, pixel samples, max depth, pixel filter) as
// option values. Call before user settings so that they override the scene.
void apply_scene_hints(Options& o, const SceneHints& hints);

// Renders o.render.frames frames. Throws OptionError / RenderError / std::runtime_error.
RenderResult render(const Scene& scene, const Options& o, const RenderHooks& hooks = {});

}  // namespace rl
