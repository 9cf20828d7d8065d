// restir_gpu_tests: SVGF's per-pixel stages on the CUDA backend (src/post/svgf_stages.cu, compiled
// with --fmad=false) against the CPU's vectorised Svgf, float for float: the same raw frames and
// AOVs (rendered on the CPU) through both. RESTIR_GPU_DRY_RUN=1 (test_gpu.cpp): the host twin
// (render.backend = cpu-bvh) stands in for the device.
#include <doctest/doctest.h>

#include <cstdlib>
#include <cstring>
#include <string>

#include "frame/render.h"
#include "post/svgf.h"
#include "denoiser_frames.h"
#include "test_helpers.h"

using namespace rl;
using namespace rl::test;

namespace {

bool svgf_dry_run() {
  const char* d = std::getenv("RESTIR_GPU_DRY_RUN");
  return d && std::string(d) == "1";
}

using Input = DenoiserInput;

// The Cornell box along its camera path (scenes/cornell-box.camera.json) under `settings`, on the CPU.
std::vector<Input> cornell_frames(std::initializer_list<const char*> settings, int frames) {
  Scene scene = load_scene(own_scene("cornell-box.pbrt"));
  load_camera_path(own_scene("cornell-box.camera.json"), scene.camera);
  Options o = options_for(scene, {"film.width=96", "film.height=72", "render.spp=1"});
  for (const char* s : settings) set_option_assignment(o, s);
  return render_denoiser_inputs(scene, o, frames, [&](int f) { return scene.camera.at_frame(f, frames); });
}

// The frames through the CPU's denoiser (render.backend = cpu) and the device's: differing floats.
size_t cpu_against_gpu(const std::vector<Input>& frames, Options o) {
  o.render.backend = Backend::cpu;
  const auto cpu = make_denoiser(o);
  o.render.backend = svgf_dry_run() ? Backend::cpu_bvh : Backend::cuda;
  const auto gpu = make_denoiser(o);
  REQUIRE(dynamic_cast<Svgf*>(gpu.get()) == nullptr);  // the stages, not the CPU's filter
  size_t differing = 0;
  Image a, b;
  for (const Input& f : frames) {
    if (!f.reshaded.empty()) cpu->set_reshaded_previous(f.reshaded), gpu->set_reshaded_previous(f.reshaded);
    cpu->denoise(f.raw, f.aovs, a);
    gpu->denoise(f.raw, f.aovs, b);
    differing += differing_floats(a, b);
  }
  return differing;
}

}  // namespace

TEST_CASE("svgf: the CUDA stages give the CPU's Svgf floats (Cornell box, camera path; pt, restir-di, a-svgf)") {
  const std::vector<Input> pt = cornell_frames({}, 8);
  const std::vector<Input> di = cornell_frames({"integrator=restir-di"}, 6);
  const std::vector<Input> reshade = cornell_frames({"denoise.method=asvgf"}, 6);
  Options o;
  set_option(o, "denoise.method", "svgf");
  const size_t pt_diff = cpu_against_gpu(pt, o), di_diff = cpu_against_gpu(di, o);
  set_option(o, "denoise.method", "asvgf");
  const size_t asvgf_diff = cpu_against_gpu(reshade, o);
  MESSAGE("differing floats, CPU Svgf against " << std::string(svgf_dry_run() ? "the host twin" : "CUDA") << ": pt " << pt_diff << " of "
                                                << 3 * pt.size() * pt[0].raw.size() << ", restir-di " << di_diff << ", a-svgf "
                                                << asvgf_diff);
  CHECK(pt_diff == 0);
  CHECK(di_diff == 0);
  CHECK(asvgf_diff == 0);
  // sigma_n = 100 is not a power of two: powf on the device, std::pow on the host (reported, not held).
  set_option(o, "denoise.method", "svgf");
  set_option(o, "denoise.sigma_n", "100");
  MESSAGE("sigma_n = 100 (pow): " << cpu_against_gpu(pt, o) << " differing floats");
}
