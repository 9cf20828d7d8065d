// The viewer's logic (issue 10), without a display: script parsing, the option panel model,
// camera control and camera paths, accumulation and views, frame-time history, and a headless
// session driven by a script (the worker thread, screenshots, what a change re-renders).
#include <doctest/doctest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "image/image_io.h"
#include "image/metrics.h"
#include "image/tonemap.h"
#include "frame/integrator.h"
#include "frame/render.h"
#include "scene/camera.h"
#include "scene/loader.h"
#include "test_helpers.h"
#include "scene/animation.h"
#include "viewer/background_reference.h"
#include "viewer/camera_controller.h"
#include "viewer/display.h"
#include "viewer/option_model.h"
#include "viewer/script.h"
#include "viewer/script_runner.h"
#include "viewer/session.h"

using namespace rl;
using namespace rl::viewer;
using namespace rl::test;
namespace fs = std::filesystem;

namespace {

std::string parse_error(const std::string& text) {
  try {
    parse_script(text, "s.txt");
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

double max_abs_diff(const Mat4& a, const Mat4& b) {
  double d = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) d = std::max(d, double(std::fabs(a.m[i][j] - b.m[i][j])));
  return d;
}

Image constant(int w, int h, float v) { return Image(w, h, Rgb(v)); }

bool same_pixels(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height) return false;
  for (size_t i = 0; i < a.size(); ++i)
    for (int c = 0; c < 3; ++c)
      if (a.pixels[i][c] != b.pixels[i][c]) return false;
  return true;
}

// Runs a script against a headless session to its end (the GUI's loop without the window).
std::string run_headless(Session& session, ScriptRunner& runner, const std::function<void(const std::string&)>& shot) {
  try {
    for (int guard = 0; guard < 1000000; ++guard) {
      const ScriptRunner::Step st = runner.step(shot);
      if (st == ScriptRunner::Step::done) return "";
      if (st == ScriptRunner::Step::waiting) {
        session.wait_frames_done();
        session.wait_reference_done();
      }
    }
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "the script did not end";
}

}  // namespace

TEST_SUITE("viewer") {
  TEST_CASE("script: commands, comments, the value of set is the rest of the line") {
    Script s = parse_script("# a comment\nset render.camera_path my path.json  \n\nframes 3 # three\nscreenshot out/a b\nquit\n", "s.txt");
    REQUIRE(s.commands.size() == 4);
    CHECK(s.commands[0].verb == "set");
    CHECK(s.commands[0].args == std::vector<std::string>{"render.camera_path", "my path.json"});
    CHECK(s.commands[0].line == 2);
    CHECK(s.commands[1].args == std::vector<std::string>{"3"});
    CHECK(s.commands[1].line == 4);
    CHECK(s.commands[2].args == std::vector<std::string>{"out/a b"});
    CHECK(s.where(s.commands[3]) == "s.txt:6");
  }

  TEST_CASE("script: each malformed line is an error naming the file and line") {
    CHECK(parse_error("frames 1\nzoom 2\n").starts_with("s.txt:2: unknown command 'zoom'"));
    CHECK(parse_error("frames 0\n").starts_with("s.txt:1: frames:"));
    CHECK(parse_error("frames 2x\n").starts_with("s.txt:1: frames:"));
    CHECK(parse_error("\n\nset key\n").starts_with("s.txt:3: set:"));
    CHECK(parse_error("view sideways\n").starts_with("s.txt:1: view:"));
    CHECK(parse_error("split 1.5\n").starts_with("s.txt:1: split:"));
    CHECK(parse_error("scale 0.3\n").starts_with("s.txt:1: scale:"));
    CHECK(parse_error("camera orbit 1\n").starts_with("s.txt:1: camera orbit:"));
    CHECK(parse_error("camera move 1 2 z\n").starts_with("s.txt:1: camera move:"));
    CHECK(parse_error("accumulate maybe\n").starts_with("s.txt:1: accumulate:"));
    CHECK(parse_error("record save\n").starts_with("s.txt:1: record:"));
    CHECK(parse_error("quit now\n").starts_with("s.txt:1: quit:"));
    CHECK(parse_error("screenshot\n").starts_with("s.txt:1: screenshot:"));
  }

  TEST_CASE("option panel: one widget per option, in order, with the documented ranges") {
    const auto values = option_values(Options{});
    const auto& widgets = option_widgets();
    REQUIRE(widgets.size() == values.size());
    for (size_t i = 0; i < values.size(); ++i) CHECK(widgets[i].key == values[i].first);
    const OptionWidget* sn = find_widget("di.spatial_neighbors");
    REQUIRE(sn);
    CHECK(sn->kind == WidgetKind::slider);
    CHECK(!sn->is_float);
    CHECK(sn->lo == 0);
    CHECK(sn->hi == 64);
    CHECK(sn->group == "di");
    CHECK(find_widget("film.width")->kind == WidgetKind::drag);  // [1, 16384]: too wide to slide
    CHECK(find_widget("output.exposure")->is_float);
    CHECK(find_widget("path.nee")->kind == WidgetKind::checkbox);
    CHECK(find_widget("render.seed")->kind == WidgetKind::seed);
    CHECK(find_widget("render.camera_path")->kind == WidgetKind::text);
    const OptionWidget* tm = find_widget("output.tonemap");
    CHECK(tm->kind == WidgetKind::combo);
    CHECK(tm->choices == std::vector<std::string>{"linear", "reinhard", "modified-reinhard", "aces"});
    const OptionWidget* in = find_widget("integrator");
    CHECK(in->kind == WidgetKind::combo);
    CHECK(in->group == "general");
    CHECK(in->choices.size() == integrator_registry().size());
    CHECK(find_widget("no.such") == nullptr);
  }

  TEST_CASE("option changes: what each invalidates; a bad value changes nothing") {
    CHECK(option_effect("output.tonemap") == Effect::display);
    CHECK(option_effect("output.exposure") == Effect::display);
    CHECK(option_effect("render.threads") == Effect::threads);
    CHECK(option_effect("di.spatial_neighbors") == Effect::restart);
    CHECK(option_effect("integrator") == Effect::restart);
    Options o;
    CHECK(apply_option(o, "di.spatial_neighbors", "7") == Effect::restart);
    CHECK(o.di.reuse.spatial_neighbors == 7);
    CHECK_THROWS_AS(apply_option(o, "di.spatial_neighbors", "65"), OptionError);
    CHECK_THROWS_AS(apply_option(o, "integrator", "no-such"), OptionError);
    CHECK(o.di.reuse.spatial_neighbors == 7);
    CHECK(o.integrator == "pt");
    // A value valid alone but not with the others (validate_options) is refused too.
    apply_option(o, "integrator", "restir-di");
    apply_option(o, "di.bsdf_candidates", "0");
    CHECK_THROWS_AS(apply_option(o, "di.light_candidates", "0"), OptionError);
    CHECK(o.di.light_candidates == 32);
    CHECK(option_value(o, "di.spatial_neighbors") == "7");
  }

  TEST_CASE("camera: starts at the scene's camera (mirrored or not), resets, orbits at a fixed distance") {
    for (const char* scene_path : {"cornell-box/scene-v4.pbrt"}) {
      Scene scene = load_scene(shared_scene(scene_path));  // pbrt's Cornell box: a mirrored camera
      const CameraKey home = scene.camera.keys.front();
      CameraController c(home, scene.bounds());
      CHECK(c.mirrored() == (home.camera_from_world.det3() < 0));
      CHECK(max_abs_diff(c.key().camera_from_world, home.camera_from_world) < 1e-4);
      CHECK(c.key().fov_degrees == home.fov_degrees);
      const float dist = length(c.target() - c.eye());
      const unsigned v0 = c.version();
      c.rotate(30, 10);
      CHECK(c.version() != v0);
      CHECK(length(c.target() - c.eye()) == doctest::Approx(dist).epsilon(1e-4));
      CHECK(max_abs_diff(c.key().camera_from_world, home.camera_from_world) > 0.1);
      c.reset();
      CHECK(max_abs_diff(c.key().camera_from_world, home.camera_from_world) < 1e-4);
      // Fly: turning keeps the eye; moving forward moves eye and target together.
      c.set_mode(CameraMode::fly);
      const Vec3 eye = c.eye();
      c.rotate(20, -5);
      CHECK(length(c.eye() - eye) < 1e-5f);
      const Vec3 t = c.target();
      c.move(Vec3(0, 0, 0.1f));
      CHECK(length((c.eye() - eye) - (c.target() - t)) < 1e-4f);
      CHECK(length(c.eye() - eye) > 0);
      // Orbit: a dolly never passes the target, and the pitch stays off the poles.
      c.reset();
      c.set_mode(CameraMode::orbit);
      c.move(Vec3(0, 0, 100));
      CHECK(length(c.target() - c.eye()) > 0);
      for (int i = 0; i < 100; ++i) c.rotate(0, 10);
      CHECK(std::fabs(dot(normalize(c.eye() - c.target()), c.up())) < 1);
    }
  }

  TEST_CASE("camera path: what the viewer records, render.camera_path reads (mirror included)") {
    Scene scene = load_scene(shared_scene("cornell-box/scene-v4.pbrt"));
    CameraController c(scene.camera.keys.front(), scene.bounds());
    c.rotate(12, 4);
    const PathKey a = c.path_key();
    c.move(Vec3(0.05f, 0, 0.1f));
    const PathKey b = c.path_key();
    const CameraKey kb = c.key();
    const fs::path dir = fs::temp_directory_path() / ("restir-viewer-path-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string file = (dir / "path.json").string();
    std::ofstream(file) << camera_path_json({a, b});
    Camera cam;
    load_camera_path(file, cam);
    fs::remove_all(dir);
    REQUIRE(cam.keys.size() == 2);
    CHECK(max_abs_diff(cam.keys[1].camera_from_world, kb.camera_from_world) < 1e-5);
    CHECK(cam.keys[1].fov_degrees == kb.fov_degrees);
    CHECK(cam.keys[1].camera_from_world.det3() < 0);  // the mirror survives the file
  }

  TEST_CASE("accumulation: the running mean since the last reset, or the last frame") {
    Accumulation acc;
    acc.add(constant(4, 2, 1));
    acc.add(constant(4, 2, 3));
    CHECK(acc.count() == 2);
    CHECK(acc.mean().at(3, 1).x == doctest::Approx(2));
    CHECK(acc.shown(false).at(0, 0).x == 3);
    CHECK(acc.shown(true).at(0, 0).x == doctest::Approx(2));
    acc.reset();
    acc.add(constant(4, 2, 5));
    CHECK(acc.count() == 1);
    CHECK(acc.mean().at(0, 0).x == 5);
    acc.add(constant(2, 2, 7));  // a new size restarts the mean
    CHECK(acc.count() == 1);
    CHECK(acc.mean().width == 2);
    CHECK(acc.mean().at(1, 1).x == 7);
  }

  TEST_CASE("views: radiance is the tone mapper's image, split shows the reference right of the cut, error map") {
    Image hdr(10, 2), ref(10, 2);
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 10; ++x) hdr.at(x, y) = Rgb(0.1f * float(x)), ref.at(x, y) = Rgb(0.5f);
    OutputOptions o;
    const Image tm = tonemap(hdr, o), tr = tonemap(ref, o);
    const Image radiance = compose_view(ViewMode::radiance, hdr, &ref, o, 0.5f);
    for (size_t i = 0; i < tm.size(); ++i) CHECK(radiance.pixels[i].x == tm.pixels[i].x);
    const Image split = compose_view(ViewMode::split, hdr, &ref, o, 0.3f);
    CHECK(split.at(2, 1).x == tm.at(2, 1).x);
    CHECK(split.at(3, 1).x == tr.at(3, 1).x);
    CHECK(split.at(9, 0).x == tr.at(9, 0).x);
    const Image err = compose_view(ViewMode::error, hdr, &ref, o, 0.5f);
    CHECK(err.at(5, 0).x == 0);  // equal to the reference: black
    CHECK(err.at(5, 0).z == 0);
    CHECK(err.at(0, 0).x == 1);  // (0 - 0.5)^2 / 0.51^2 ~ 1: red
    CHECK(err.at(4, 0).y == 1);  // (0.4 - 0.5)^2 / 0.51^2 = 0.038: between green (0.01) and yellow (0.1)
    CHECK(err.at(4, 0).x > 0.5f);
    // Without a reference of the right size every view is the radiance view.
    const Image small = constant(3, 2, 0.5f);
    const Image fallback = compose_view(ViewMode::error, hdr, &small, o, 0.5f);
    CHECK(fallback.at(7, 1).x == tm.at(7, 1).x);
    const Image none = compose_view(ViewMode::split, hdr, nullptr, o, 0.5f);
    CHECK(none.at(9, 1).x == tm.at(9, 1).x);
  }

  TEST_CASE("downsample: box filter over blocks") {
    Image img(4, 2);
    for (int x = 0; x < 4; ++x) img.at(x, 0) = Rgb(float(x)), img.at(x, 1) = Rgb(float(x) + 4);
    const Image d = downsample(img, 2);
    REQUIRE(d.width == 2);
    REQUIRE(d.height == 1);
    CHECK(d.at(0, 0).x == doctest::Approx((0 + 1 + 4 + 5) / 4.0));
    CHECK(d.at(1, 0).y == doctest::Approx((2 + 3 + 6 + 7) / 4.0));
  }

  TEST_CASE("frame history: the last N frame times, oldest first") {
    FrameHistory h(3);
    CHECK(h.mean_ms() == 0);
    CHECK(h.fps() == 0);
    for (double ms : {10.0, 20.0, 30.0, 40.0}) h.add(ms);
    CHECK(h.values() == std::vector<float>{20, 30, 40});
    CHECK(h.mean_ms() == doctest::Approx(30));
    CHECK(h.mean_ms(1) == doctest::Approx(40));
    CHECK(h.fps(1) == doctest::Approx(25));
    h.clear();
    h.add(5);
    CHECK(h.values() == std::vector<float>{5});
  }

  TEST_CASE("FrameRenderer: a reset integrator renders what a new one renders") {
    Scene scene = load_scene(own_scene("cornell-box.pbrt"));
    Options o = options_for(scene, {"integrator=restir-di", "film.width=16", "film.height=9", "render.spp=1"});
    const CameraKey key = scene.camera.keys.front();
    FrameRenderer a(scene, o);
    Image x, y, z;
    a.render_frame(key, 1, x, nullptr);
    a.render_frame(key, 1, y, nullptr);
    CHECK(a.frames_rendered() == 2);
    a.reset(o);
    CHECK(a.frames_rendered() == 0);
    a.render_frame(key, 1, z, nullptr);
    for (size_t i = 0; i < x.size(); ++i) CHECK(z.pixels[i].x == x.pixels[i].x);
    Options bad = o;
    bad.integrator = "no-such";
    CHECK_THROWS_AS(a.reset(bad), OptionError);
    a.render_frame(key, 1, z, nullptr);  // the old integrator is still there
  }

  TEST_CASE("headless session: with denoise.method set the view is the denoised frame") {
    const fs::path dir = fs::temp_directory_path() / ("restir-viewer-denoise-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    std::vector<Image> shots;
    for (const char* method : {"denoise.method=none", "denoise.method=svgf"}) {
      ViewArgs args;
      args.scene = own_scene("cornell-box.pbrt");
      args.sets = {"film.width=24", "film.height=16", method};
      Session session(args);
      ViewState view;
      const std::string base = (dir / (std::string(method).substr(15))).string();
      ScriptRunner runner(parse_script("frames 1\nscreenshot " + base + "\n", "t.txt"), session, view);
      session.render_frames(0);
      session.start({});
      auto shot = [&](const std::string& b) {
        Image hdr;
        FrameReadout r;
        session.take_frame(view.accumulate, true, hdr, r);
        session.screenshot(b, hdr, compose_view(view.mode, hdr, nullptr, session.options().output, view.split), r, "{}");
      };
      CHECK(run_headless(session, runner, shot).empty());
      session.stop();
      shots.push_back(read_image(base + ".exr"));
    }
    CHECK(shots[0].pixels != shots[1].pixels);  // the same seed and frame: only the denoiser differs
    fs::remove_all(dir);
  }

  TEST_CASE("headless session: a script renders, changes options and writes screenshots") {
    const fs::path dir = fs::temp_directory_path() / ("restir-viewer-session-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string d = dir.string();
    ViewArgs args;
    args.scene = own_scene("cornell-box.pbrt");
    args.sets = {"film.width=24", "film.height=16"};
    Session session(args);
    ViewState view;
    ScriptRunner runner(parse_script("frames 2\nscreenshot " + d + "/a\nset output.tonemap reinhard\nscreenshot " + d +
                                         "/b\nset path.max_depth 1\nframes 1\nscreenshot " + d + "/c\nsave-config " + d +
                                         "/cfg.json\nset path.max_depth 9999\n",
                                     "t.txt"),
                        session, view);
    session.render_frames(0);
    session.start({});
    // What the GUI does for a screenshot, without the window.
    auto shot = [&](const std::string& base) {
      Image hdr;
      FrameReadout r;
      session.take_frame(view.accumulate, true, hdr, r);
      session.screenshot(base, hdr, compose_view(view.mode, hdr, nullptr, session.options().output, view.split), r, "{}");
    };
    const std::string error = run_headless(session, runner, shot);
    session.stop();
    CHECK(error.starts_with("t.txt:9: option 'path.max_depth'"));
    const Image a = read_image(d + "/a.exr"), b = read_image(d + "/b.exr"), c = read_image(d + "/c.exr");
    const Image pa = read_image(d + "/a.png"), pb = read_image(d + "/b.png");
    CHECK(a.width == 24);
    double dexr = 0, dpng = 0, dc = 0;
    for (size_t i = 0; i < a.size(); ++i) {
      dexr += std::fabs(a.pixels[i].x - b.pixels[i].x);
      dpng += std::fabs(pa.pixels[i].x - pb.pixels[i].x);
      dc += std::fabs(a.pixels[i].x - c.pixels[i].x);
    }
    CHECK(dexr == 0);  // the tone mapper did not re-render
    CHECK(dpng > 0);   // but changed the PNG
    CHECK(dc > 0);     // path.max_depth restarted the render
    std::ifstream side(d + "/c.json");
    std::stringstream ss;
    ss << side.rdbuf();
    CHECK(ss.str().find("\"frames_accumulated\": 1") != std::string::npos);
    Options saved;
    apply_options_file(saved, d + "/cfg.json");
    CHECK(saved.path.max_depth == 1);
    CHECK(saved.output.tonemap == Tonemap::reinhard);
    CHECK(saved.film.width == 24);
    fs::remove_all(dir);
  }

  TEST_CASE("redraw pacing: input at once, a new frame within the budget, at least once a second") {
    DrawPacer p(0.05);
    CHECK(p.due(0, false, false));  // never drawn: the once-a-second redraw is due
    p.drawn(0, 0.02, false);        // a 20 ms redraw: at 5% the next new frame waits 0.4 s
    CHECK(p.cost_s() == doctest::Approx(0.02).scale(1e-9));
    CHECK_FALSE(p.due(0.1, false, true));
    CHECK(p.wait_s(0.1, true) == doctest::Approx(0.3).scale(1e-9));
    CHECK(p.due(0.4, false, true));
    CHECK_FALSE(p.due(0.5, false, false));  // nothing new: no redraw
    CHECK(p.due(1.0, false, false));        // but once a second
    CHECK(p.due(0.1, true, false));         // input draws at once ...
    p.drawn(0.1, 0.02, true);
    for (int i = 0; i < 3; ++i) {  // ... and settles for three more redraws
      CHECK(p.due(0.11, false, false));
      CHECK(p.wait_s(0.11, false) == doctest::Approx(1.0 / 60).scale(1e-9));
      p.drawn(0.11, 0.02, false);
    }
    CHECK_FALSE(p.due(0.12, false, false));
    DrawPacer every(1.0);  // budget 100%: every new frame once the last redraw is done
    every.drawn(0, 0.02, false);
    CHECK(every.due(0.021, false, true));
    CHECK_FALSE(every.due(0.019, false, true));
  }

  TEST_CASE("background reference: the path tracer of the viewer's integral, view and pose, its own seed") {
    Scene scene = load_scene(own_scene("cornell-box.pbrt"));
    Options defaults;
    apply_scene_hints(defaults, scene.hints);
    const Options o = options_for(scene, {"integrator=restir-di", "film.width=16", "film.height=12", "render.spp=1", "path.max_depth=5"});
    const CameraKey key = scene.camera.keys.front();
    BackgroundReference bg(scene, defaults);
    CHECK(bg.aim(o, key, 0));
    for (int i = 0; i < 6; ++i) bg.pass();
    CHECK(bg.spp() == 6);
    // Exactly `restir render` of the reference options over as many one-sample frames.
    Options r = reference_options(defaults, o);
    CHECK(r.integrator == "pt");
    CHECK(r.path.max_depth == 1);  // restir-di estimates direct light
    r.render.spp = 1;
    r.render.frames = 6;
    r.render.seed = reference_seed(o.render.seed);
    CHECK(r.render.seed != o.render.seed);  // noise independent of the frames it is compared with
    Scene seen = scene;
    seen.camera.keys = {key};
    CHECK(same_pixels(render(seen, r).average, bg.mean()));
    // ReSTIR's options, the tone mapper and the thread count leave it alone ...
    Options same = o;
    same.di.reuse.spatial_neighbors = 0;
    same.di.light_candidates = 4;
    same.output.tonemap = Tonemap::aces;
    same.render.threads = 1;
    CHECK_FALSE(bg.aim(same, key, 5));  // (a static scene has one pose)
    CHECK(bg.spp() == 6);
    // ... the integral, the camera, the film and the seed restart it.
    Options pt = o;
    pt.integrator = "pt";
    CHECK(bg.aim(pt, key, 0));
    CHECK(bg.spp() == 0);
    CHECK(bg.options().path.max_depth == 5);
    CameraKey turned = key;
    turned.fov_degrees += 1;
    CHECK(bg.aim(pt, turned, 0));
    pt.film.width = 17;
    CHECK(bg.aim(pt, turned, 0));
    pt.render.seed = 9;
    CHECK(bg.aim(pt, turned, 0));
  }

  TEST_CASE("the reference's own relMSE: the variance of a mean of n passes over pbrt's denominator") {
    // Synthetic passes with a known spread: pixel i has mean m_i and takes m_i +- s_i (each with
    // probability 1/2), so the variance of one pass is s_i^2 and of the mean of n, s_i^2 / n.
    const int w = 40, h = 30, n = 8;
    Pcg32 rng(7, 1);
    Image mean(w, h);
    std::vector<double> squares(size_t(w) * h * 3, 0.0);
    double expected = 0;
    for (int i = 0; i < w * h; ++i) {
      const float m = 0.05f + 0.9f * rng.next_float(), sd = 0.5f * m;
      for (int c = 0; c < 3; ++c) {
        double sum = 0, sum2 = 0;
        for (int k = 0; k < n; ++k) {
          const double v = m + (rng.next_float() < 0.5f ? -sd : sd);
          sum += v, sum2 += v * v;
        }
        mean.pixels[i][c] = float(sum / n);
        squares[size_t(i) * 3 + c] = sum2 / n;
        // Over the mean's own denominator, as the estimate has it (the true m would be ~9% off here).
        const double d = mean.pixels[i][c] + 0.01;
        expected += double(sd) * sd / n / (d * d);
      }
    }
    expected /= w * h * 3;
    const double est = rel_mse_of_mean(mean, squares, n);
    INFO("estimate " << est << ", expected " << expected);
    CHECK(est == doctest::Approx(expected).epsilon(0.05));  // dividing by n instead of n - 1 is 12.5% low
    CHECK(rel_mse_of_mean(mean, squares, 1) == -1);
  }

  TEST_CASE("the background reference's own relMSE predicts its distance to another, independent one") {
    // Two references of one view with independent seeds: E[relMSE(A, B)] ~ own(A) + own(B), the
    // variances add (the denominator's own noise makes the left a little larger).
    Scene scene = load_scene(own_scene("cornell-box.pbrt"));
    Options defaults;
    apply_scene_hints(defaults, scene.hints);
    // Random pixel positions: the default Halton pattern does not depend on the seed, so two
    // references would share their positions and their anti-aliasing noise (measured: relMSE(A, B)
    // 0.4x own(A) + own(B)).
    Options o = options_for(scene, {"integrator=pt", "film.width=24", "film.height=18", "render.spp=1", "path.max_depth=1",
                                    "render.sample_pattern=random"});
    defaults.render.sample_pattern = SamplePattern::random;  // the reference's options start from these
    const CameraKey key = scene.camera.keys.front();
    BackgroundReference a(scene, defaults), b(scene, defaults);
    CHECK(a.aim(o, key, 0));
    o.render.seed += 1;
    CHECK(b.aim(o, key, 0));
    CHECK(a.own_rel_mse() == -1);
    for (int i = 0; i < 32; ++i) a.pass(), b.pass();
    const double own = a.own_rel_mse() + b.own_rel_mse(), between = rel_mse(a.mean(), b.mean());
    INFO("relMSE(A, B) " << between << ", own(A) + own(B) " << own);
    CHECK(a.own_rel_mse() > 0);
    CHECK(between / own > 0.6);
    CHECK(between / own < 1.7);
  }

  TEST_CASE("background reference of an animated scene: the scene frozen at the viewer's frame, held after the last key") {
    Scene scene = load_scene(own_scene("dynamic-room.pbrt"));
    REQUIRE(scene_animated(scene));
    Options defaults;
    apply_scene_hints(defaults, scene.hints);
    const Options o = options_for(scene, {"integrator=pt", "film.width=12", "film.height=8", "render.spp=1", "path.max_depth=2"});
    const CameraKey key = scene.camera.keys.front();
    BackgroundReference bg(scene, defaults);
    CHECK(bg.aim(o, key, 10));  // the switched light is off from frame 8 on
    for (int i = 0; i < 3; ++i) bg.pass();
    Options r = bg.options();
    r.render.frames = 3;
    Scene frozen = scene_at_frame(scene, 10);
    frozen.camera.keys = {key};
    CHECK(same_pixels(render(frozen, r).average, bg.mean()));
    CHECK(bg.aim(o, key, 11));        // the sweeping light moved
    CHECK(bg.aim(o, key, 40));        // past the last key (32) ...
    CHECK_FALSE(bg.aim(o, key, 90));  // ... the pose holds
  }

  TEST_CASE("headless session: the background reference follows the view and feeds the metrics") {
    const fs::path dir = fs::temp_directory_path() / ("restir-viewer-bgref-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string d = dir.string();
    ViewArgs args;
    args.scene = own_scene("cornell-box.pbrt");
    args.sets = {"film.width=16", "film.height=12", "integrator=restir-di"};
    Session session(args);
    CHECK(session.reference() == nullptr);
    ViewState view;
    Image first;
    int shots = 0;
    auto shot = [&](const std::string&) {
      Image hdr;
      FrameReadout r;
      session.take_frame(view.accumulate, true, hdr, r);
      REQUIRE(session.reference() != nullptr);
      if (shots++ == 0) first = *session.reference();
      CHECK(r.reference_spp == 32);
      CHECK(session.reference_spp() == 32);
      if (shots > 1) return;
      // The frames converge to it: restir-di's mean over 8 frames is near the reference's. Both
      // are noisy at these counts, so only the image mean, of luminance clamped to 1 (pixels that
      // see the light, at ~17, would otherwise decide it alone).
      double m = 0, mr = 0;
      for (size_t i = 0; i < hdr.size(); ++i)
        m += std::min(1.0f, luminance(hdr.pixels[i])), mr += std::min(1.0f, luminance(session.reference()->pixels[i]));
      CHECK(m == doctest::Approx(mr).epsilon(0.05));
    };
    ScriptRunner runner(parse_script("set film.width 20\nset film.width 16\nreference on 32\nframes 8\nreference wait\nscreenshot " + d + "/a\n"
                                     "set di.spatial_neighbors 0\nframes 1\nscreenshot " + d + "/b\n"
                                     "camera orbit 10 0\nframes 1\nreference wait\nscreenshot " + d + "/c\n",
                                     "t.txt"),
                        session, view);
    session.render_frames(0);
    session.start({});
    const std::string error = run_headless(session, runner, shot);
    session.stop();
    CHECK(error == "");
    CHECK(shots == 3);
    // The reference of the turned camera is another image; ReSTIR's option did not restart it.
    CHECK_FALSE(same_pixels(first, *session.reference()));
    fs::remove_all(dir);
  }

  TEST_CASE("script: reference commands") {
    const Script s = parse_script("reference on\nreference on 64\nreference off\nreference wait\n", "s.txt");
    CHECK(s.commands.size() == 4);
    CHECK(parse_error("reference on 0") == "s.txt:1: reference on: '0' is not a sample count in [1, 16777216]");
    CHECK(parse_error("reference maybe").starts_with("s.txt:1: reference: expected"));
    CHECK(parse_error("reference wait 3").starts_with("s.txt:1: reference: expected"));
    ViewArgs args;
    args.scene = own_scene("cornell-box.pbrt");
    args.sets = {"film.width=8", "film.height=8"};
    Session session(args);
    ViewState view;
    ScriptRunner runner(parse_script("reference wait\n", "w.txt"), session, view);
    CHECK_THROWS_WITH_AS(runner.step([](const std::string&) {}), "w.txt:1: reference wait: no background reference with a target (reference on SPP)",
                         std::runtime_error);
  }
}
