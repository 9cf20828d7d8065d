// The `restirlab._core` extension module (issue 47): exceptions, scenes, options, studies. The
// renderer is bound in renderer.cpp, images and metrics in images.cpp; restirlab/__init__.py is
// the public face.
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/shared_ptr.h>

#include "bindings.h"
#include "backends/backend_error.h"
#include "core/build_info.h"
#include "core/io_error.h"
#include "frame/integrator.h"
#include "frame/options.h"
#include "image/image_io.h"
#include "scene/loader.h"
#include "study/runner.h"
#include "study/study_file.h"

namespace rl::py {

std::vector<std::pair<std::string, std::string>> option_assignments(nb::handle options) {
  std::vector<std::pair<std::string, std::string>> out;
  if (options.is_none()) return out;
  if (!nb::isinstance<nb::dict>(options)) throw OptionError("options: expected a dict of option keys and values");
  // Depth first, in the dict's order, so that later keys override earlier ones as --set does.
  auto walk = [&](auto& self, nb::dict d, const std::string& prefix) -> void {
    for (auto [k, v] : d) {
      if (!nb::isinstance<nb::str>(k)) throw OptionError("options: keys must be strings, got " + nb::cast<std::string>(nb::repr(k)));
      const std::string key = prefix.empty() ? nb::cast<std::string>(k) : prefix + "." + nb::cast<std::string>(k);
      if (nb::isinstance<nb::dict>(v)) self(self, nb::borrow<nb::dict>(v), key);
      else if (nb::isinstance<nb::bool_>(v)) out.emplace_back(key, nb::cast<bool>(v) ? "true" : "false");
      else if (nb::isinstance<nb::int_>(v) || nb::isinstance<nb::float_>(v)) out.emplace_back(key, nb::cast<std::string>(nb::repr(v)));
      else if (nb::isinstance<nb::str>(v)) out.emplace_back(key, nb::cast<std::string>(v));
      else
        throw OptionError("option '" + key + "': unsupported value type '" +
                          nb::cast<std::string>(nb::type_name(v.type())) + "' (use a str, int, float or bool)");
    }
  };
  walk(walk, nb::borrow<nb::dict>(options), "");
  return out;
}

namespace {

void bind_errors(nb::module_& m) {
  // The library's exception types, each under the Python built-in that says what went wrong; the
  // message is the CLI's `error: ...` line without the prefix.
  nb::exception<OptionError>(m, "OptionError", PyExc_ValueError);
  nb::exception<SceneError>(m, "SceneError", PyExc_ValueError);
  nb::exception<study::StudyError>(m, "StudyError", PyExc_ValueError);
  nb::exception<ImageError>(m, "ImageError", PyExc_OSError);
  nb::exception<IoError>(m, "IoError", PyExc_OSError);
  nb::exception<RenderError>(m, "RenderError", PyExc_RuntimeError);
  nb::exception<BackendError>(m, "BackendError", PyExc_RuntimeError);
}

void bind_scene(nb::module_& m) {
  // Held by shared_ptr: a Renderer keeps its scene alive (FrameRenderer refers to it).
  nb::class_<Scene>(m, "Scene", "A loaded scene (pbrt-v4, OBJ, glTF, PLY), as `restir render` reads it.")
      .def_prop_ro("triangle_count", &Scene::triangle_count)
      .def_prop_ro("input_files", [](const Scene& s) { return s.input_files; }, "the files the scene was read from");
  m.def("load_scene", [](const std::string& path) {
        nb::gil_scoped_release unlocked;  // parsing and mesh loading take a while; nothing Python runs
        return std::make_shared<Scene>(load_scene(path));
      },
      nb::arg("path"), "Loads a scene file (throws SceneError naming the file and line).");
}

void bind_options(nb::module_& m) {
  m.def("options_help", [](const std::string& prefix) { return options_help(prefix); }, nb::arg("prefix") = "",
        "Every option key with its type, default and meaning (`restir options PREFIX`).");
  m.def("integrators", [] {
        std::vector<std::pair<std::string, std::string>> out;
        for (const auto& i : integrator_registry()) out.emplace_back(i.name, i.description);
        return out;
      }, "(name, description) of every integrator.");
  m.def("build_id", [] { return std::string(build_id()); }, "The version and source hash of this build.");
}

void bind_study(nb::module_& m) {
  m.def("run_study", [](const std::string& name, const std::string& out, bool quick, int jobs, bool quiet) {
        study::StudyArgs a;
        a.study = name, a.out = out, a.quick = quick, a.jobs = jobs, a.quiet = quiet;
        nb::gil_scoped_release unlocked;
        return study::run_study(a);
      },
      nb::arg("study"), nb::arg("out"), nb::arg("quick") = false, nb::arg("jobs") = 1, nb::arg("quiet") = true,
      "`restir study STUDY --out OUT`: returns its exit status (0: done).");
}

}  // namespace

}  // namespace rl::py

NB_MODULE(_core, m) {
  using namespace rl::py;
  m.doc() = "restir-lab's renderer, metrics and studies (bindings; see restirlab/__init__.py)";
  bind_errors(m);
  bind_scene(m);
  bind_options(m);
  bind_renderer(m);
  bind_images(m);
  bind_study(m);
}
