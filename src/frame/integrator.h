// The integrator interface and registry. One file per algorithm; an integrator renders frames of
// a sequence into an HDR image. Virtual dispatch happens once per frame, never per sample.
#pragma once
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "image/image.h"
#include "frame/frame_buffer.h"
#include "frame/frame_world.h"
#include "frame/options.h"
#include "frame/planted_bias.h"
#include "frame/stage_times.h"
#include "backends/cpu/accel.h"
#include "scene/camera.h"
#include "scene/lights.h"

namespace rl {

// A render that cannot produce a correct image (e.g. non-finite radiance) fails loudly.
struct RenderError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct RenderContext {
  const Scene& scene;
  const Accel& accel;
  const Lights& lights;
  const Options& options;
  const PlantedBias* planted = nullptr;  // tests only: see planted_bias.h
};

// The context's scene and lights as the per-sample code reads them (host views, no copy). Build it
// once per stage, not per sample: it is ~380 bytes.
inline PathWorld path_world(const RenderContext& ctx) { return {ctx.accel.scene_view(), ctx.lights.view(), ctx.accel.ray_epsilon()}; }

struct FrameInfo {
  int index = 0;                 // frame number in the sequence
  int count = 1;                 // frames in the sequence
  const PerspectiveCamera* camera = nullptr;
  const PerspectiveCamera* previous_camera = nullptr;  // null on the first frame
  // An animated scene's lights as they were one frame earlier (Lights::follow carries history
  // samples to where their emitters moved); null when no light moves or on the first frame.
  const Lights* previous_lights = nullptr;
  // An animated scene as it was one frame earlier, with its own BVH: given (from the second
  // frame on) only to an integrator whose needs_previous_scene() says so, which evaluates the
  // history's targets there (GRIS: each domain's target in its own scene). Null otherwise.
  const Scene* previous_scene = nullptr;
  const Accel* previous_accel = nullptr;
  std::function<void(int, int)> progress;              // (tiles done, tiles) for a progress bar; may be empty
  StageTimes* stages = nullptr;                        // where the integrator records its stages' wall time; may be null
};

// The previous frame's scene, BVH and lights as a RenderContext (ctx's options and planted
// biases), when the renderer kept them (FrameInfo::previous_scene); empty otherwise.
inline std::optional<RenderContext> previous_context(const RenderContext& ctx, const FrameInfo& frame) {
  if (!frame.previous_scene || !frame.previous_accel) return std::nullopt;
  return RenderContext{*frame.previous_scene, *frame.previous_accel,
                       frame.previous_lights ? *frame.previous_lights : ctx.lights, ctx.options, ctx.planted};
}

// The checks of render.debug_view (the ReSTIR views, frame/reuse_pixel.h) that every integrator
// makes: one with no debug views refuses them all, one whose samples have no path refuses
// reconnection-depth. `why` ends the message.
void refuse_debug_views(const RenderContext& ctx, const char* why);
void refuse_reconnection_depth(const RenderContext& ctx, const char* why);

class Integrator {
 public:
  virtual ~Integrator() = default;
  // Renders one frame into `out` (already sized to the film); called for frames 0, 1, ... in order.
  virtual void render_frame(const FrameInfo& frame, Image& out) = 0;
  // True when render_frame wants FrameInfo::previous_scene / previous_accel (the renderer then
  // keeps a second, one-frame-old copy of an animated scene and its BVH: twice the animation cost).
  virtual bool needs_previous_scene() const { return false; }
  // A-SVGF's temporal gradients (Schied et al. 2018, sec. 4; src/post/asvgf.h) need the previous
  // frame's samples shaded again in this frame's scene with their own random numbers. True when
  // rerender_previous can do that: an integrator without state between frames (pt) renders frame
  // f-1's FrameInfo again; a ReSTIR integrator, whose frame f-1 started from the history of f-2,
  // keeps a copy of that history (keep_history) and renders f-1 again from it.
  virtual bool rerenders_previous() const { return false; }
  // Called once, before the first frame, by a renderer that will call rerender_previous.
  virtual void keep_history(bool) {}
  // Renders `previous` (frame f-1's FrameInfo, in frame f's scene) into `out` from the state frame
  // f-1 started from; the integrator's state afterwards is what it was (frame f+1 is unaffected).
  virtual void rerender_previous(const FrameInfo& previous, Image& out) { render_frame(previous, out); }
  // Bytes of every buffer the integrator holds (capacities, in the backend's memory): its state,
  // which the benchmarks report per pixel (issue 48's compact-state targets). 0: not reported.
  virtual size_t buffer_bytes() const { return 0; }
  // The last frame in the integrator's own buffer, in the backend's memory (the chains' or samples'
  // average, before any denoiser): height x width RGB float triples, overwritten by the next
  // frame, freed with the integrator. Null where the frame has no such buffer (ssr) or gets more
  // on the host (restir-pt with pt.direct = restir-di adds ReSTIR DI's image there). The Python
  // API hands it over without a copy (frame_buffer.h).
  virtual FrameBuffer frame_buffer() const { return {}; }
};

// The bytes an execution policy's array holds (Exec::Array<T>: capacity elements).
template <class A>
size_t array_bytes(const A& a) {
  return a.capacity * sizeof(*a.data);
}

// A frame's RGB array in execution policy Exec's memory as Integrator::frame_buffer (none unless
// holds_frame: the array holds the frame shown).
template <class Exec, class A>
FrameBuffer frame_buffer_of(const A& rgb, bool holds_frame) {
  static_assert(sizeof(*rgb.data) == 3 * sizeof(float), "RGB float triples");
  if (!holds_frame) return {};
  return {reinterpret_cast<const float*>(rgb.data), Exec::kOnDevice, Exec::device_id()};
}

// One row of the registry (src/integrators/registry.cpp): an algorithm, the option groups it
// reads and how to make it on each backend. A new integrator is one folder and a row.
struct IntegratorInfo {
  const char* name;
  const char* description;
  // The option groups it reads besides film.*, render.* and output.*, which every integrator reads
  // (e.g. "path pt di"): a key of another group set explicitly is an error (check_option_groups).
  const char* reads;
  // Refuses options or scenes it cannot render, with an OptionError; on every backend. May be null.
  void (*check)(const RenderContext&);
  std::unique_ptr<Integrator> (*make)(const RenderContext&);       // render.backend = cpu or cpu-bvh
  std::unique_ptr<Integrator> (*make_cuda)(const RenderContext&);  // render.backend = cuda; null: none in this build
  bool reads_group(std::string_view group) const;
};

const std::vector<IntegratorInfo>& integrator_registry();
// Both throw OptionError for an unknown name, listing the known ones.
const IntegratorInfo& find_integrator(const std::string& name);
// The integrator's check, then its maker for o.render.backend; a CUDA backend that fails (no device,
// too little memory) is an OptionError naming render.backend.
std::unique_ptr<Integrator> make_integrator(const std::string& name, const RenderContext& ctx);
// Throws OptionError for a key set explicitly (Options::explicit_keys) that o.integrator does not
// read, naming the integrator and the groups it reads: a typo'd or misplaced sweep axis would
// otherwise change nothing, silently.
void check_option_groups(const Options& o);

}  // namespace rl
