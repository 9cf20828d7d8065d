// The public entry point: render a scene with options into HDR frames. The CLI and the study
// harness drive integrators only through this.
#pragma once
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "image/image.h"
#include "frame/aov.h"
#include "frame/frame_buffer.h"
#include "frame/options.h"
#include "frame/planted_bias.h"
#include "frame/stage_times.h"
#include "scene/camera.h"
#include "scene/scene.h"

namespace rl {

struct RenderResult {
  Image last;                    // the last frame of the sequence
  Image average;                 // mean of all frames (converges for static scenes)
  std::vector<double> frame_ms;  // wall time of each frame
  std::vector<StageTimes> frame_stages;  // wall time of each frame's stages (stage_times.h)
  // The last frame after the post-process stage (denoise.method); empty when it is none. `last` and
  // `average` stay the integrator's raw frames.
  Image denoised;
  // The integrator's buffers after the last frame (Integrator::buffer_bytes; 0: not reported).
  size_t buffer_bytes = 0;
};

struct RenderHooks {
  // Called after each frame with its image and wall time.
  std::function<void(int frame, const Image& image, double ms)> on_frame;
  bool progress_bar = false;     // draw a progress bar on stderr
  const PlantedBias* planted = nullptr;  // tests only (planted_bias.h)
  // Called after each frame with its AOVs (frame/aov.h); when set, the renderer builds them.
  std::function<void(int frame, const Aovs& aovs)> on_aovs;
  // Called after each frame with its denoised image (only when denoise.method != none).
  std::function<void(int frame, const Image& denoised)> on_denoised;
};

// Applies what the scene file says (Film resolution, pixel samples, max depth, pixel filter) as
// option values. Call before user settings so that they override the scene.
void apply_scene_hints(Options& o, const SceneHints& hints);

// The path tracer's options whose converged image an unbiased run of `o` converges to: pt on o's
// film and path length (restir-di estimates direct light only: depth 1), every other option from
// `defaults` (the scene's hints), no camera path, the display transform at its defaults. The
// sample count, seed, frames and threads are the caller's to set. Used by the study's cached
// references and the viewer's background reference, so both compare against the same integral.
Options reference_options(const Options& defaults, const Options& o);

class Accel;
class RayLog;
class Lights;
struct RenderContext;
class Integrator;
class ThreadLimit;
class Denoiser;

// One integrator kept alive across frames, with the scene's BVH and lights, so that ReSTIR's
// temporal history carries from frame to frame. render() drives one over a sequence; the viewer
// keeps one for a whole session and calls reset() when an option changes.
class FrameRenderer {
 public:
  // Validates o and builds the BVH, the lights and the integrator (throws OptionError for bad options).
  FrameRenderer(const Scene& scene, const Options& o, const PlantedBias* planted = nullptr);
  ~FrameRenderer();
  FrameRenderer(const FrameRenderer&) = delete;
  FrameRenderer& operator=(const FrameRenderer&) = delete;

  // New options: a fresh integrator (no history; the next frame is frame 0); the lights are rebuilt
  // only when the light selection changed, the BVH never (it depends on the scene alone).
  void reset(const Options& o);
  // The next frame is frame `frame` of the sequence (its animation pose, camera path key and
  // random streams), with no history: a fresh integrator and denoiser, as after reset(). An
  // integrator without state between frames (pt) renders exactly the sequence's frame `frame`.
  // Throws OptionError unless 0 <= frame < render.frames.
  void seek(int frame);
  // Renders the next frame (index 0, 1, ... since the last reset) of a sequence of `count` frames
  // seen through `key`, sized film.width x film.height; the previous frame's camera is passed on
  // for reprojection. An animated scene is first moved to that frame (its BVH refitted, its
  // lights rebuilt if they move). Throws RenderError when a pixel is not finite. Returns the wall time in ms.
  double render_frame(const CameraKey& key, int count, Image& out, StageTimes* stages,
                      const std::function<void(int, int)>& progress = {});
  // A new worker thread count (render.threads); the integrator and its history stay.
  void set_threads(int threads);
  // Benchmarks: every ray the CPU backend traces from now on is also appended to `log` (null: off).
  void set_ray_log(RayLog* log);
  const Options& options() const { return o_; }
  int frames_rendered() const { return frame_; }
  // The integrator's buffers (Integrator::buffer_bytes): its state, for the state per pixel.
  size_t buffer_bytes() const;
  // The last frame in the integrator's own buffer (Integrator::frame_buffer), overwritten by the
  // next frame. *owner (unless null) keeps that buffer alive: holding it, the view stays valid after
  // reset() or seek() replaced the integrator (showing the frame it showed) and after this renderer.
  FrameBuffer frame_buffer(std::shared_ptr<const void>* owner = nullptr) const;
  // Build the AOVs of every frame from now on, even without a denoiser (which needs them anyway).
  void request_aovs(bool on) { aovs_requested_ = on; }
  // The last frame's AOVs: empty (width 0) unless requested or denoise.method != none.
  const Aovs& aovs() const { return aovs_; }
  // The last frame after the post-process stage; empty when denoise.method = none. The frame that
  // render_frame wrote into `out` stays the integrator's raw one.
  const Image& denoised() const { return denoised_; }
  // A-SVGF: the previous frame rendered again in the last frame's scene (Integrator::rerender_previous);
  // empty before the second frame or without denoise.method = asvgf.
  const Image& reshaded() const { return reshaded_; }

 private:
  RenderContext context() const;
  void post_process(const PerspectiveCamera& cam, const Image& raw, StageTimes* stages);
  void check_denoiser();
  const Scene& rest_;  // the scene as loaded (the rest pose of an animated scene)
  // An animated scene's current frame (animate_scene), which the BVH, the lights and the
  // integrator see; the loaded scene itself when nothing is animated.
  Scene animated_;
  const Scene& scene_;
  const PlantedBias* planted_;
  Options o_;  // the integrator's RenderContext refers to it: the object never moves
  std::unique_ptr<Accel> accel_;
  std::unique_ptr<Lights> lights_;
  std::unique_ptr<Lights> previous_lights_;  // lights that move: as they were one frame earlier
  // The animated scene one frame earlier and its BVH, kept only for an integrator that asks
  // (Integrator::needs_previous_scene); built on first use.
  Scene previous_scene_;
  std::unique_ptr<Accel> previous_accel_;
  int previous_shown_ = -1;  // the frame previous_scene_ shows
  std::unique_ptr<ThreadLimit> limit_;
  // Shared: a frame_buffer() view may keep a replaced integrator's buffer (and so the integrator) alive.
  std::shared_ptr<Integrator> integrator_;
  std::unique_ptr<Denoiser> denoiser_;  // the post-process stage (null: denoise.method = none)
  bool aovs_requested_ = false;
  Aovs aovs_;
  Image denoised_;
  Image reshaded_;  // A-SVGF: the previous frame's samples shaded in this frame
  std::optional<PerspectiveCamera> previous_;
  std::optional<PerspectiveCamera> before_previous_;  // A-SVGF: frame f-2's camera, the previous frame's previous
  int frame_ = 0;
  int shown_frame_ = 0;  // the frame animated_ (and the BVH and lights built from it) shows: 0 after construction
};

// Renders o.render.frames frames. Throws OptionError / RenderError, BackendError (Embree, the CUDA device).
RenderResult render(const Scene& scene, const Options& o, const RenderHooks& hooks = {});

// mean <- mean + (img - mean) / count: the running mean after the count-th image (same size).
void accumulate_mean(Image& mean, const Image& img, int count);

}  // namespace rl
