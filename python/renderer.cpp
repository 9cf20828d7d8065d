// restirlab.Renderer: a FrameRenderer (src/frame/render.h) kept alive across frames, with its frame
// in an Image that Python sees without a copy, and Ctrl-C able to stop a long frame.
#include <nanobind/stl/array.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/shared_ptr.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <chrono>
#include <type_traits>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "bindings.h"
#include "frame/integrator.h"
#include "frame/options.h"
#include "frame/render.h"
#include "scene/camera.h"

namespace rl::py {

namespace {

// The options `restir render` would use for the same arguments, set in the same order: the scene's
// hints, the dedicated flags (--integrator, --spp, --frames, --threads, --seed), then each key as a
// --set, then the integrator's defaults for a sequence. The same errors, the same messages.
struct Settings {
  std::optional<std::string> integrator;
  std::optional<int> spp, frames, threads;
  std::optional<uint64_t> seed;
  bool aovs = false;
};

// A copy of an AOV array (T: packed floats or uint32) as a numpy array that owns it.
template <class T>
nb::object owned_array(const std::vector<T>& v, std::initializer_list<size_t> shape) {
  using Scalar = std::conditional_t<std::is_same_v<T, uint32_t>, uint32_t, float>;
  static_assert(sizeof(T) % sizeof(Scalar) == 0);
  auto* held = new std::vector<T>(v);
  nb::capsule owner(held, [](void* p) noexcept { delete static_cast<std::vector<T>*>(p); });
  return nb::cast(nb::ndarray<nb::numpy, Scalar>(reinterpret_cast<Scalar*>(held->data()), shape.size(), shape.begin(), owner));
}
Options resolve_options(const Scene& scene, const Settings& s, nb::handle options, std::vector<std::string>& notes) {
  Options o;
  apply_scene_hints(o, scene.hints);
  if (s.integrator) set_option(o, "integrator", *s.integrator);
  if (s.spp) set_option(o, "render.spp", std::to_string(*s.spp));
  if (s.frames) set_option(o, "render.frames", std::to_string(*s.frames));
  if (s.threads) set_option(o, "render.threads", std::to_string(*s.threads));
  if (s.seed) set_option(o, "render.seed", std::to_string(*s.seed));
  for (const auto& [k, v] : option_assignments(options)) set_option(o, k, v);
  notes = fit_defaults_to_integrator(o, /*sequence=*/true);
  validate_options(o);
  find_integrator(o.integrator);
  return o;
}

// Thrown from the progress callback when a Python signal handler raised (Ctrl-C): it unwinds the
// frame, through TBB, back to render_frame, where the Python error is still set.
struct Interrupted {};

// Polls Python's signal handlers from the progress callback, on the thread that called
// render_frame (the only one where PyErr_CheckSignals runs them) and at most every 50 ms: the GIL
// is taken briefly, the rendering threads never wait for it.
std::function<void(int, int)> signal_poll() {
  using clock = std::chrono::steady_clock;
  return [caller = std::this_thread::get_id(), next = clock::now()](int, int) mutable {
    if (std::this_thread::get_id() != caller || clock::now() < next) return;
    next = clock::now() + std::chrono::milliseconds(50);
    nb::gil_scoped_acquire locked;
    if (PyErr_CheckSignals() != 0) throw Interrupted{};
  };
}

// The cameras of the sequence, as render() finds them: the camera path's keys, or the scene's camera.
Camera camera_of(const Scene& scene, const Options& o) {
  Camera camera = scene.camera;
  if (!o.render.camera_path.empty()) load_camera_path(o.render.camera_path, camera);
  if (camera.keys.empty()) camera.keys.push_back(CameraKey{});
  return camera;
}

class PyRenderer {
  // First: the FrameRenderer refers to the scene, which must outlive it (members die in reverse order).
  std::shared_ptr<Scene> scene_;

 public:
  PyRenderer(std::shared_ptr<Scene> scene, const Settings& s, nb::handle options) : scene_(std::move(scene)) {
    const Options o = resolve_options(*scene_, s, options, notes_);
    for (const std::string& n : notes_)
      if (n.starts_with("warning: ")) PyErr_WarnEx(PyExc_RuntimeWarning, n.c_str() + 9, 1);
    camera_ = camera_of(*scene_, o);
    nb::gil_scoped_release unlocked;  // the BVH build
    renderer_ = std::make_unique<FrameRenderer>(*scene_, o);
    renderer_->request_aovs(s.aovs);
    // Allocated once: image() views stay valid as long as the renderer (the film size never changes).
    image_ = Image(o.film.width, o.film.height);
  }

  // The next frame, seen through `camera` or the scene's camera (path) at this frame.
  void render_frame(const std::optional<CameraKey>& camera) {
    const std::unique_lock busy = claim("render_frame");
    const Options& o = renderer_->options();
    const CameraKey key = camera ? *camera : camera_.at_frame(renderer_->frames_rendered(), o.render.frames);
    stages_ = StageTimes{};
    const auto poll = signal_poll();
    try {
      nb::gil_scoped_release unlocked;
      has_frame_ = false;
      frame_ms_ = renderer_->render_frame(key, o.render.frames, image_, &stages_, poll);
      has_frame_ = true;
    } catch (const Interrupted&) {
      // A frame stopped half way leaves a half-updated history: start over at frame 0.
      renderer_->reset(Options(renderer_->options()));
      throw nb::python_error();  // the KeyboardInterrupt the signal handler raised
    }
    if (PyErr_CheckSignals() != 0) throw nb::python_error();  // Ctrl-C during a frame that never polled
  }

  // New option values on top of the current ones; the history restarts (frame 0).
  void reset(nb::handle options) {
    const std::unique_lock busy = claim("reset");
    Options o = renderer_->options();
    for (const auto& [k, v] : option_assignments(options)) set_option(o, k, v);
    if (o.film.width != image_.width || o.film.height != image_.height)
      throw OptionError("reset: film.width and film.height are fixed for a Renderer (image() views share its buffer); make a new Renderer");
    validate_options(o);
    Camera camera = camera_of(*scene_, o);
    {
      nb::gil_scoped_release unlocked;
      renderer_->reset(o);
    }
    has_frame_ = false;
    camera_ = std::move(camera);
  }

  // The last frame in the integrator's own buffer, without a copy (FrameRenderer::frame_buffer): a
  // DLPack array on the backend's device, which keeps the buffer (and this renderer) alive.
  nb::ndarray<nb::array_api> frame_buffer() {
    const std::unique_lock busy = claim("frame_buffer");
    if (!has_frame_) throw std::runtime_error("frame_buffer(): no frame rendered since the Renderer was made, reset() or seek()");
    auto* keep = new std::pair<std::shared_ptr<const void>, nb::object>{nullptr, nb::borrow(nb::find(this))};
    const FrameBuffer fb = renderer_->frame_buffer(&keep->first);
    nb::capsule owner(keep, [](void* p) noexcept { delete static_cast<std::pair<std::shared_ptr<const void>, nb::object>*>(p); });
    if (!fb.rgb)
      throw std::runtime_error("frame_buffer(): this frame has no buffer of its own in the backend's memory (restir-pt with "
                               "pt.direct=restir-di, which adds ReSTIR DI's image on the host; denoise.method=asvgf, which renders "
                               "the previous frame into it again): use image()");
    const size_t shape[3] = {size_t(image_.height), size_t(image_.width), 3};
    return nb::ndarray<nb::array_api>(const_cast<float*>(fb.rgb), 3, shape, owner, nullptr, nb::dtype<float>(),
                         fb.on_device ? nb::device::cuda::value : nb::device::cpu::value, fb.device_id);
  }

  // The next frame is `frame` of the sequence, the history dropped (FrameRenderer::seek).
  void seek(int frame) {
    const std::unique_lock busy = claim("seek");
    nb::gil_scoped_release unlocked;
    renderer_->seek(frame);
    has_frame_ = false;
  }

  nb::dict stage_times() const {
    nb::dict d;
    for (const auto& [name, ms] : stages_.ms) d[name.c_str()] = ms;
    return d;
  }
  // The rays each stage of the last frame traced, by kind (core/ray_counter.h), and "frame": all.
  nb::dict ray_counts() const {
    nb::dict d;
    const auto entry = [](const RayCounts& c) {
      nb::dict e;
      e["closest"] = c.closest;
      e["any"] = c.any;
      e["queued"] = c.queued;  // of the any-hit ones, those a queued reuse pass traced in one stage (render.reuse_rays)
      return e;
    };
    for (const auto& [name, c] : stages_.rays) d[name.c_str()] = entry(c);
    d["frame"] = entry(stages_.total_rays());
    return d;
  }
  nb::dict options() const {
    nb::dict d;
    for (const auto& [k, v] : option_values(renderer_->options())) d[k.c_str()] = v;
    return d;
  }
  CameraKey camera_at(int frame) const { return camera_.at_frame(frame, renderer_->options().render.frames); }

  // The last frame's AOVs (frame/aov.h) as arrays (copies: the renderer refills its own each frame).
  nb::dict aovs() const {
    const Aovs& a = renderer_->aovs();
    if (a.width == 0)
      throw std::runtime_error(renderer_->frames_rendered() == 0 ? "aovs(): no frame rendered yet"
                                                                  : "aovs(): make the Renderer with aovs=True (or a denoise.method)");
    const size_t h = size_t(a.height), w = size_t(a.width);
    nb::dict d;
    d["albedo"] = owned_array(a.albedo, {h, w, 3});
    d["normal"] = owned_array(a.normal, {h, w, 3});
    d["depth"] = owned_array(a.depth, {h, w});
    d["depth_gradient"] = owned_array(a.depth_gradient, {h, w});
    d["motion"] = owned_array(a.motion, {h, w, 2});
    d["emission"] = owned_array(a.emission, {h, w, 3});
    d["surface_id"] = owned_array(a.surface_id, {h, w});
    return d;
  }
  // The last frame after denoise.method (a copy), or None when it is none.
  nb::object denoised() const {
    const Image& d = renderer_->denoised();
    if (d.width == 0) return nb::none();
    return nb::cast(image_array(Image(d)));
  }

  Image image_;
  std::vector<std::string> notes_;
  double frame_ms_ = 0;
  std::unique_ptr<FrameRenderer> renderer_;

 private:
  // The GIL is released while a frame renders: a second Python thread calling in meanwhile is refused,
  // not raced.
  std::unique_lock<std::mutex> claim(const char* what) {
    std::unique_lock lock(busy_, std::try_to_lock);
    if (!lock.owns_lock()) throw std::runtime_error(std::string("Renderer.") + what + ": the renderer is rendering in another thread");
    return lock;
  }
  std::mutex busy_;
  bool has_frame_ = false;  // the integrator's buffer holds a frame (frame_buffer())
  Camera camera_;
  StageTimes stages_;
};

void bind_camera(nb::module_& m) {
  nb::class_<CameraKey>(m, "Camera", "A pinhole camera: where it is, where it looks, its field of view.")
      .def_static("look_at", [](std::array<float, 3> eye, std::array<float, 3> target, std::array<float, 3> up, float fov) {
            if (!(fov > 0 && fov < 180)) throw OptionError("Camera.look_at: fov must be in (0, 180) degrees");
            CameraKey k;
            k.fov_degrees = fov;
            if (!look_at(Vec3(eye[0], eye[1], eye[2]), Vec3(target[0], target[1], target[2]), Vec3(up[0], up[1], up[2]), k.camera_from_world))
              throw OptionError("Camera.look_at: eye, target and up do not define a camera");
            return k;
          },
          nb::arg("eye"), nb::arg("target"), nb::arg("up") = std::array<float, 3>{0, 1, 0}, nb::arg("fov") = 90.0f,
          "A camera at `eye` looking at `target`; fov (degrees) spans the image's shorter axis.")
      .def_rw("fov", &CameraKey::fov_degrees);
}

}  // namespace

void bind_renderer(nb::module_& m) {
  bind_camera(m);
  nb::class_<PyRenderer>(m, "Renderer",
                         "An integrator kept alive across frames (ReSTIR's temporal history carries over), as "
                         "`restir render --frames N` drives it.")
      .def("__init__", [](PyRenderer* self, std::shared_ptr<Scene> scene, std::optional<std::string> integrator,
                          std::optional<nb::dict> options, std::optional<int> spp, std::optional<int> frames,
                          std::optional<uint64_t> seed, std::optional<int> threads, bool aovs) {
            new (self) PyRenderer(std::move(scene), Settings{integrator, spp, frames, threads, seed, aovs}, dict_or_none(options));
          },
          nb::arg("scene"), nb::arg("integrator") = nb::none(), nb::arg("options") = nb::none(), nb::kw_only(),
          nb::arg("spp") = nb::none(), nb::arg("frames") = nb::none(), nb::arg("seed") = nb::none(),
          nb::arg("threads") = nb::none(), nb::arg("aovs") = false,
          "aovs=True: build the AOVs of every frame (aovs()). Options as a dict, nested or with dotted keys ({'pt.shift': 'hybrid'}); spp, frames, seed and threads are "
          "the CLI's --spp, --frames, --seed and --threads. Bad options raise OptionError with the CLI's message.")
      .def("render_frame", &PyRenderer::render_frame, nb::arg("camera") = nb::none(),
           "Renders the next frame (the GIL is released; Ctrl-C raises KeyboardInterrupt and restarts the history). "
           "camera: this frame's camera instead of the scene's.")
      .def("image", [](PyRenderer& r) { return image_view(r.image_, nb::find(&r)); },
           "The last frame, H x W x 3 float32 linear RGB: a view of the renderer's buffer (no copy), overwritten by "
           "each render_frame(); it keeps the renderer alive.")
      .def("reset", [](PyRenderer& r, std::optional<nb::dict> options) { r.reset(dict_or_none(options)); },
           nb::arg("options") = nb::none(),
           "New option values (film size excepted) on top of the current ones; the history restarts at frame 0.")
      .def("frame_buffer", &PyRenderer::frame_buffer,
           "The last frame in the integrator's own buffer, H x W x 3 float32, without a copy, as a DLPack array on the "
           "backend's device: host memory for render.backend cpu / cpu-bvh (numpy.from_dlpack), the GPU's for cuda "
           "(torch.from_dlpack, cupy.from_dlpack). Before any denoiser. Overwritten by the next frame; the array keeps "
           "the buffer alive, so after reset() or seek() it still shows the frame it showed. Not for restir-pt "
           "with pt.direct=restir-di or denoise.method=asvgf (RuntimeError: use image()).")
      .def("seek", &PyRenderer::seek, nb::arg("frame"),
           "The next render_frame() renders frame `frame` of the sequence (0 <= frame < frames): the animated scene's "
           "pose, the camera path's key and the random streams of that frame, with no history (the integrator starts "
           "over there, as after reset()). pt, which keeps no history, renders exactly the CLI's frame `frame`.")
      .def("aovs", &PyRenderer::aovs,
           "The last frame's AOVs (needs aovs=True or a denoise.method), copies: albedo, normal (world, unit, toward the "
           "camera) and emission H x W x 3; depth (linear view depth, camera-space z) and depth_gradient H x W; motion "
           "H x W x 2 (pixels to the previous frame's position); surface_id H x W uint32 (0xffffffff: no surface). "
           "docs/denoise.md describes each.")
      .def("denoised", &PyRenderer::denoised, "The last frame after denoise.method (a copy), or None when it is none.")
      .def("stage_times", &PyRenderer::stage_times, "Wall time (ms) of each stage of the last frame.")
      .def("ray_counts", &PyRenderer::ray_counts,
           "Rays each stage of the last frame traced: {stage: {'closest': n, 'any': n, 'queued': n}} ('queued': of the any-hit "
           "rays, those render.reuse_rays=queued traced in one stage), and 'frame' for all of them "
           "(divide by film.width * film.height for rays per pixel).")
      .def("options", &PyRenderer::options, "Every option's value as text, as `restir render` echoes them.")
      .def("camera", &PyRenderer::camera_at, nb::arg("frame"), "The scene's camera (path) at a frame of the sequence.")
      .def_prop_ro("frame_ms", [](const PyRenderer& r) { return r.frame_ms_; }, "Wall time (ms) of the last frame.")
      .def_prop_ro("frame", [](const PyRenderer& r) { return r.renderer_->frames_rendered(); },
                   "The index of the next frame: frames rendered since construction, reset() or seek().")
      .def_prop_ro("frames", [](const PyRenderer& r) { return r.renderer_->options().render.frames; },
                   "render.frames: the sequence's length (the camera path is spread over it).")
      .def_prop_ro("notes", [](const PyRenderer& r) { return r.notes_; },
                   "What the CLI prints as notes: defaults fitted to the integrator.")
      .def_prop_ro("width", [](const PyRenderer& r) { return r.image_.width; })
      .def_prop_ro("height", [](const PyRenderer& r) { return r.image_.height; });
}

}  // namespace rl::py
