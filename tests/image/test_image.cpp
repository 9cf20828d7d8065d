// Tests of src/image: EXR/PNG I/O, atomic writes, sRGB, tone mappers, error metrics.
#include <doctest/doctest.h>
#include <OpenEXR/ImfArray.h>
#include <OpenEXR/ImfRgbaFile.h>
#include <stb_image.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>

#include "image/image_io.h"
#include "image/metrics.h"
#include "image/tonemap.h"
#include "test_helpers.h"

using namespace rl;
namespace fs = std::filesystem;

namespace {

// A fresh scratch directory per test case, removed afterwards.
struct TempDir {
  fs::path dir;
  TempDir() {
    static int counter = 0;
    dir = fs::temp_directory_path() / ("restir_test_image_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  std::string operator/(const std::string& name) const { return (dir / name).string(); }
  // Names in the directory containing ".tmp-" (left-over temp files of atomic writes).
  int temp_files() const {
    int n = 0;
    for (const auto& e : fs::directory_iterator(dir))
      if (e.path().filename().string().find(".tmp-") != std::string::npos) ++n;
    return n;
  }
};

// Message of the exception thrown by f (empty if none).
template <class F>
std::string thrown_message(F&& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return {};
}

Image gradient(int w, int h) {
  Image img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img.at(x, y) = Rgb(float(x) / w, float(y) / h, 0.25f + 0.01f * float(x + y));
  return img;
}

OutputOptions opts(Tonemap t, float exposure = 0, bool srgb = false, float white = 4) {
  OutputOptions o;
  o.tonemap = t;
  o.exposure = exposure;
  o.srgb = srgb;
  o.white_point = white;
  return o;
}

}  // namespace

TEST_SUITE("image") {

// ---------------------------------------------------------------------------------------------
// EXR

TEST_CASE("EXR float round trip is exact, including negative, tiny and large values, row 0 on top") {
  TempDir t;
  const int w = 7, h = 5;  // non-square, odd: catches transposed or flipped reads
  Image img(w, h);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-10.f, 10.f);
  for (auto& p : img.pixels) p = Rgb(u(rng), u(rng), u(rng));
  img.at(0, 0) = Rgb(-3.5f, 1e20f, 3.0e38f);
  img.at(w - 1, 0) = Rgb(1e-30f, -1e-40f /* denormal */, 65504.f);
  img.at(0, h - 1) = Rgb(0.1f, 1.0f / 3.0f, -0.0f);
  write_exr(t / "a.exr", img);
  Image back = read_image(t / "a.exr");
  REQUIRE(back.width == w);
  REQUIRE(back.height == h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      CAPTURE(x);
      CAPTURE(y);
      CHECK(back.at(x, y) == img.at(x, y));
    }
  // Overwriting an existing file works and gives the new content.
  Image other(3, 2, Rgb(2.f, 4.f, 8.f));
  write_exr(t / "a.exr", other);
  Image back2 = read_image(t / "a.exr");
  CHECK(back2.width == 3);
  CHECK(back2.at(2, 1) == Rgb(2.f, 4.f, 8.f));
  CHECK(t.temp_files() == 0);
}

TEST_CASE("EXR metadata round trip") {
  TempDir t;
  const std::string json = "{\n  \"integrator\": \"pt\",\n  \"render.spp\": 64,\n  \"note\": \"caf\xc3\xa9 \\\"q\\\"\"\n}";
  std::vector<std::pair<std::string, std::string>> md = {
      {"restir.config", json}, {"restir.version", "0.1.0"}, {"restir.empty", ""}};
  write_exr(t / "m.exr", gradient(4, 3), md);
  auto back = read_exr_metadata(t / "m.exr");
  auto find = [&](const std::string& k) -> const std::string* {
    for (auto& [name, value] : back)
      if (name == k) return &value;
    return nullptr;
  };
  REQUIRE(find("restir.config"));
  CHECK(*find("restir.config") == json);
  REQUIRE(find("restir.version"));
  CHECK(*find("restir.version") == "0.1.0");
  REQUIRE(find("restir.empty"));
  CHECK(find("restir.empty")->empty());
  // Only string attributes: the standard (non-string) header attributes are not listed.
  CHECK(find("compression") == nullptr);
  CHECK(find("dataWindow") == nullptr);
  CHECK(back.size() == 3);
  // Pixel data unaffected by metadata.
  CHECK(mse(read_image(t / "m.exr"), gradient(4, 3)) == 0.0);
  // A name that collides with a standard attribute is refused, and nothing is written.
  CHECK_THROWS_AS(write_exr(t / "bad.exr", gradient(2, 2), {{"compression", "x"}}), std::runtime_error);
  CHECK_FALSE(fs::exists(t / "bad.exr"));
}

TEST_CASE("atomic writes: no temp file left, failures throw and never clobber the target") {
  TempDir t;
  const Image img = gradient(4, 4);

  SUBCASE("success leaves only the target") {
    write_exr(t / "ok.exr", img);
    write_png(t / "ok.png", img);
    write_text_file_atomic(t / "ok.json", "{\"a\": 1}\n");
    CHECK(t.temp_files() == 0);
    CHECK(test::read_file(t / "ok.json") == "{\"a\": 1}\n");
    write_text_file_atomic(t / "ok.json", "replaced");
    CHECK(test::read_file(t / "ok.json") == "replaced");
    CHECK(t.temp_files() == 0);
  }
  SUBCASE("a directory as target path") {
    fs::create_directories(t / "dir.exr");
    std::string msg = thrown_message([&] { write_exr(t / "dir.exr", img); });
    CHECK(msg.find("dir.exr") != std::string::npos);
    CHECK(fs::is_directory(t / "dir.exr"));
    CHECK_THROWS_AS(write_png(t / "dir.exr", img), std::runtime_error);
    CHECK_THROWS_AS(write_text_file_atomic(t / "dir.exr", "x"), std::runtime_error);
    CHECK(fs::is_directory(t / "dir.exr"));
    CHECK(t.temp_files() == 0);
  }
  SUBCASE("an I/O failure while writing keeps the existing file intact") {
    write_text_file_atomic(t / "keep.exr", "precious");
    write_text_file_atomic(t / "keep.png", "precious");
    write_text_file_atomic(t / "keep.csv", "precious");
    // Occupy the temp paths with directories: opening the temp file for writing fails.
    const std::string pid = std::to_string(::getpid());
    for (const char* n : {"keep.exr", "keep.png", "keep.csv"}) fs::create_directories(t / (std::string(n) + ".tmp-" + pid));
    CHECK_THROWS_AS(write_exr(t / "keep.exr", img), std::runtime_error);
    CHECK_THROWS_AS(write_png(t / "keep.png", img), std::runtime_error);
    CHECK_THROWS_AS(write_text_file_atomic(t / "keep.csv", "new"), std::runtime_error);
    CHECK(test::read_file(t / "keep.exr") == "precious");
    CHECK(test::read_file(t / "keep.png") == "precious");
    CHECK(test::read_file(t / "keep.csv") == "precious");
    // The directories are not ours to delete.
    CHECK(fs::is_directory(t / ("keep.exr.tmp-" + pid)));
  }
  SUBCASE("an invalid image is refused before anything is written") {
    write_text_file_atomic(t / "keep.exr", "precious");
    Image broken(4, 4);
    broken.pixels.resize(3);
    CHECK_THROWS_AS(write_exr(t / "keep.exr", broken), std::runtime_error);
    CHECK_THROWS_AS(write_exr(t / "empty.exr", Image()), std::runtime_error);
    CHECK(test::read_file(t / "keep.exr") == "precious");
    CHECK_FALSE(fs::exists(t / "empty.exr"));
    CHECK(t.temp_files() == 0);
  }
  SUBCASE("a missing directory") {
    std::string msg = thrown_message([&] { write_exr(t / "no/such/dir/x.exr", img); });
    CHECK(msg.find("no/such/dir/x.exr") != std::string::npos);
  }
}

TEST_CASE("shared env map: 1024x512 DWAB reads as finite radiance, agreeing with OpenEXR's RGBA reader") {
  const std::string path = RESTIR_SHARED_DIR "/scenes/envmaps/courtyard.exr";
  if (!fs::exists(path)) {
    MESSAGE("skipped: " << path << " not present");
    return;
  }
  Image env = read_image(path);
  REQUIRE(env.width == 1024);
  REQUIRE(env.height == 512);
  ImageStats s = image_stats(env);
  CHECK(s.nan_count == 0);
  CHECK(s.inf_count == 0);
  // DWAB is lossy (DCT): its ringing leaves a few tiny negative values in the file itself (an
  // independent reader sees the same ~1.2k pixels, min ~ -0.003). The file is read faithfully;
  // consumers that need radiance >= 0 (env-map sampling) clamp. Here: rare and tiny.
  CHECK(s.negative_count < env.width * env.height / 100);
  float min_value = 0;
  for (const Rgb& p : env.pixels) min_value = std::min({min_value, p.x, p.y, p.z});
  CHECK(min_value > -0.01f);
  MESSAGE("courtyard mean luminance " << s.mean_luminance << ", negative pixels " << s.negative_count);
  // Plausible sky radiance: neither black nor absurd, and not constant.
  CHECK(s.mean_luminance > 0.05);
  CHECK(s.mean_luminance < 50);
  Image flat(env.width, env.height, Rgb(float(s.mean_luminance)));
  CHECK(mean_abs_error(env, flat) > 1e-2);

  // Independent reference: OpenEXR's RgbaInputFile (half precision, its own channel mapping).
  Imf::RgbaInputFile f(path.c_str());
  const Imath::Box2i dw = f.dataWindow();
  Imf::Array2D<Imf::Rgba> px(env.height, env.width);
  f.setFrameBuffer(&px[0][0] - dw.min.x - size_t(dw.min.y) * size_t(env.width), 1, size_t(env.width));
  f.readPixels(dw.min.y, dw.max.y);
  int mismatches = 0;
  for (int y = 0; y < env.height; ++y)
    for (int x = 0; x < env.width; ++x) {
      const Imf::Rgba& q = px[y][x];
      Rgb a = env.at(x, y), b(float(q.r), float(q.g), float(q.b));
      for (int c = 0; c < 3; ++c)
        if (std::fabs(a[c] - b[c]) > 1e-3f * std::fabs(b[c]) + 1e-6f) ++mismatches;
    }
  CHECK(mismatches == 0);
}

TEST_CASE("EXR layouts written by OpenEXR's RGBA writer: half RGBA (DWAB, PIZ), Y only, Y/RY/BY") {
  TempDir t;
  const int w = 32, h = 16;
  Image img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img.at(x, y) = Rgb(0.1f + x * 0.05f, 2.f + y * 0.25f, 0.5f);
  auto write_rgba = [&](const std::string& path, Imf::RgbaChannels ch, Imf::Compression comp) {
    Imf::Array2D<Imf::Rgba> px(h, w);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) px[y][x] = Imf::Rgba(img.at(x, y).x, img.at(x, y).y, img.at(x, y).z, 1.f);
    Imf::RgbaOutputFile out(path.c_str(), w, h, ch, 1, Imath::V2f(0, 0), 1, Imf::INCREASING_Y, comp);
    out.setFrameBuffer(&px[0][0], 1, size_t(w));
    out.writePixels(h);
  };
  SUBCASE("half RGBA, PIZ: exact to half precision") {
    write_rgba(t / "piz.exr", Imf::WRITE_RGBA, Imf::PIZ_COMPRESSION);
    Image back = read_image(t / "piz.exr");
    REQUIRE(back.width == w);
    REQUIRE(back.height == h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c) CHECK(back.at(x, y)[c] == float(half(img.at(x, y)[c])));
  }
  SUBCASE("half RGB, DWAB (lossy): close") {
    write_rgba(t / "dwab.exr", Imf::WRITE_RGB, Imf::DWAB_COMPRESSION);
    Image back = read_image(t / "dwab.exr");
    REQUIRE(back.width == w);
    CHECK(rel_mse(back, img) < 1e-3);
  }
  SUBCASE("luminance only: grey replicated to RGB") {
    write_rgba(t / "y.exr", Imf::WRITE_Y, Imf::ZIP_COMPRESSION);
    Image back = read_image(t / "y.exr");
    REQUIRE(back.width == w);
    for (int x = 0; x < w; x += 7) {
      Rgb p = back.at(x, 3);
      CHECK(p.x == p.y);
      CHECK(p.y == p.z);
      CHECK(p.x == doctest::Approx(luminance(img.at(x, 3))).epsilon(2e-3).scale(1e-9));
    }
  }
  SUBCASE("luminance/chroma: converted back to RGB") {
    write_rgba(t / "yc.exr", Imf::WRITE_YC, Imf::ZIP_COMPRESSION);
    Image back = read_image(t / "yc.exr");
    REQUIRE(back.width == w);
    CHECK(rel_mse(back, img) < 1e-3);
  }
}

TEST_CASE("PNG write -> stb read round trip within 1/255; read_image decodes sRGB to linear") {
  TempDir t;
  const int w = 9, h = 4;
  Image img(w, h);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  for (auto& p : img.pixels) p = Rgb(u(rng), u(rng), u(rng));
  img.at(0, 0) = Rgb(-1.f, 2.f, std::numeric_limits<float>::quiet_NaN());  // clamped: 0, 1, NaN -> 0
  write_png(t / "a.png", img);

  int rw = 0, rh = 0, n = 0;
  unsigned char* data = stbi_load((t / "a.png").c_str(), &rw, &rh, &n, 3);
  REQUIRE(data);
  REQUIRE(rw == w);
  REQUIRE(rh == h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) {
        float expect = std::clamp(std::isnan(img.at(x, y)[c]) ? 0.f : img.at(x, y)[c], 0.f, 1.f);
        float got = data[3 * (y * w + x) + c] / 255.f;
        CHECK(std::fabs(got - expect) <= 0.5f / 255.f + 1e-6f);
      }
  stbi_image_free(data);

  Image lin = read_image(t / "a.png");
  REQUIRE(lin.width == w);
  for (int x = 1; x < w; ++x)
    for (int c = 0; c < 3; ++c) {
      // 8-bit quantization of the encoded value, then decode: slope of decode is <= 2.4 -> bound.
      CHECK(std::fabs(lin.at(x, 2)[c] - srgb_decode(img.at(x, 2)[c])) <= 2.5f / 255.f);
    }
  CHECK(lin.at(0, 0) == Rgb(0.f, 1.f, 0.f));
}

// ---------------------------------------------------------------------------------------------
// Errors when reading

TEST_CASE("reading a missing, malformed, truncated or unsupported file throws with the path") {
  TempDir t;
  std::string msg = thrown_message([&] { read_image(t / "missing.exr"); });
  CHECK(msg.find(t / "missing.exr") != std::string::npos);
  CHECK(thrown_message([&] { read_image(t / "missing.png"); }).find("missing.png") != std::string::npos);
  CHECK(thrown_message([&] { read_exr_metadata(t / "missing.exr"); }).find("missing.exr") != std::string::npos);

  SUBCASE("truncated EXR") {
    Image img = gradient(64, 64);
    write_exr(t / "full.exr", img);
    std::string bytes = test::read_file(t / "full.exr");
    REQUIRE(bytes.size() > 100);
    for (size_t keep : {bytes.size() / 2, size_t(20), size_t(0)}) {
      CAPTURE(keep);
      {
        std::ofstream f(t / "cut.exr", std::ios::binary | std::ios::trunc);
        f.write(bytes.data(), std::streamsize(keep));
      }
      std::string m = thrown_message([&] { read_image(t / "cut.exr"); });
      CHECK(m.find("cut.exr") != std::string::npos);
    }
  }
  SUBCASE("garbage with an image extension") {
    write_text_file_atomic(t / "junk.exr", "this is not an image at all, just text");
    write_text_file_atomic(t / "junk.png", "this is not an image at all, just text");
    write_text_file_atomic(t / "junk.hdr", "this is not an image at all, just text");
    CHECK(thrown_message([&] { read_image(t / "junk.exr"); }).find("junk.exr") != std::string::npos);
    CHECK(thrown_message([&] { read_image(t / "junk.png"); }).find("junk.png") != std::string::npos);
    CHECK(thrown_message([&] { read_image(t / "junk.hdr"); }).find("junk.hdr") != std::string::npos);
  }
  SUBCASE("unsupported extension and directories") {
    write_text_file_atomic(t / "a.xyz", "x");
    CHECK(thrown_message([&] { read_image(t / "a.xyz"); }).find(".xyz") != std::string::npos);
    CHECK_THROWS_AS(read_image(t.dir.string()), std::runtime_error);
  }
}

// ---------------------------------------------------------------------------------------------
// sRGB and tone mapping

TEST_CASE("sRGB transfer: known values and inverse") {
  CHECK(srgb_encode(0.f) == 0.f);
  CHECK(srgb_encode(1.f) == doctest::Approx(1.f).epsilon(1e-6).scale(1e-9));
  CHECK(srgb_encode(0.5f) == doctest::Approx(0.735357f).epsilon(1e-5).scale(1e-9));
  // The knee: both pieces meet at linear 0.0031308 <-> encoded 0.04045 (continuity).
  CHECK(srgb_encode(0.0031308f) == doctest::Approx(0.04045f).epsilon(1e-4).scale(1e-9));
  CHECK(1.055f * std::pow(0.0031308f, 1.f / 2.4f) - 0.055f == doctest::Approx(0.04045f).epsilon(1e-3).scale(1e-9));
  CHECK(srgb_encode(0.001f) == doctest::Approx(0.01292f).epsilon(1e-6).scale(1e-9));  // linear segment
  CHECK(srgb_decode(0.04045f) == doctest::Approx(0.0031308f).epsilon(1e-4).scale(1e-9));
  CHECK(srgb_decode(0.735357f) == doctest::Approx(0.5f).epsilon(1e-5).scale(1e-9));
  for (int i = 0; i <= 1000; ++i) {
    float v = float(i) / 1000.f;
    CHECK(srgb_decode(srgb_encode(v)) == doctest::Approx(v).epsilon(1e-5).scale(1e-9).scale(1e-6));
    CHECK(srgb_encode(srgb_decode(v)) == doctest::Approx(v).epsilon(1e-5).scale(1e-9).scale(1e-6));
    if (i > 0) CHECK(srgb_encode(v) > srgb_encode(float(i - 1) / 1000.f));
  }
}

TEST_CASE("tone mappers are monotonic and map [0,inf) into [0,1]") {
  for (Tonemap tm : {Tonemap::linear, Tonemap::reinhard, Tonemap::modified_reinhard, Tonemap::aces})
    for (bool srgb : {false, true})
      for (Rgb colour : {Rgb(1.f), Rgb(1.f, 0.5f, 0.1f), Rgb(0.05f, 0.2f, 1.f)}) {
        CAPTURE(int(tm));
        CAPTURE(srgb);
        OutputOptions o = opts(tm, 0, srgb);
        Rgb prev = tonemap_pixel(Rgb(0.f), o);
        CHECK(prev == Rgb(0.f));
        for (int i = 1; i <= 2000; ++i) {
          float s = 1e-3f * std::pow(1.01f, float(i));  // 1e-3 .. ~4e5
          Rgb v = tonemap_pixel(colour * s, o);
          for (int c = 0; c < 3; ++c) {
            CHECK(v[c] >= prev[c] - 1e-6f);  // monotonic up to float rounding of colour * s
            CHECK(v[c] >= 0.f);
            CHECK(v[c] <= 1.f);
          }
          prev = v;
        }
      }
}

TEST_CASE("tone mapper known values") {
  SUBCASE("linear clamps") {
    OutputOptions o = opts(Tonemap::linear);
    CHECK(tonemap_pixel(Rgb(0.25f, 0.5f, 0.75f), o) == Rgb(0.25f, 0.5f, 0.75f));
    CHECK(tonemap_pixel(Rgb(-1.f, 2.f, 1e30f), o) == Rgb(0.f, 1.f, 1.f));
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    CHECK(tonemap_pixel(Rgb(nan, inf, -inf), o) == Rgb(0.f, 1.f, 0.f));
    CHECK(tonemap_pixel(Rgb(0.5f), opts(Tonemap::linear, 0, true)).x == doctest::Approx(srgb_encode(0.5f)));
  }
  SUBCASE("Reinhard: L = 1 -> 0.5, colour ratio kept") {
    OutputOptions o = opts(Tonemap::reinhard);
    Rgb g = tonemap_pixel(Rgb(1.f), o);
    CHECK(g.x == doctest::Approx(0.5f));
    CHECK(g.y == doctest::Approx(0.5f));
    CHECK(tonemap_pixel(Rgb(3.f), o).x == doctest::Approx(0.75f));
    Rgb c = tonemap_pixel(Rgb(0.4f, 0.2f, 0.1f), o);
    CHECK(c.x / c.y == doctest::Approx(2.f));
    CHECK(luminance(c) == doctest::Approx(luminance(Rgb(0.4f, 0.2f, 0.1f)) / (1 + luminance(Rgb(0.4f, 0.2f, 0.1f)))));
    const float inf = std::numeric_limits<float>::infinity();
    Rgb big = tonemap_pixel(Rgb(inf, 1.f, 1.f), o);
    CHECK(is_finite(big));
  }
  SUBCASE("modified Reinhard: L = white point -> 1") {
    for (float lw : {1.f, 2.f, 4.f, 11.2f}) {
      OutputOptions o = opts(Tonemap::modified_reinhard, 0, false, lw);
      CHECK(tonemap_pixel(Rgb(lw), o).y == doctest::Approx(1.f).epsilon(1e-6).scale(1e-9));
      CHECK(tonemap_pixel(Rgb(0.9f * lw), o).y < 0.9999f);
      CHECK(tonemap_pixel(Rgb(1.5f * lw), o).y == 1.f);
      // eq. 4 at L = 1: (1 + 1/lw^2) / 2
      CHECK(tonemap_pixel(Rgb(1.f), o).y == doctest::Approx(std::min(1.f, 0.5f * (1 + 1 / (lw * lw)))));
    }
  }
  SUBCASE("ACES (Narkowicz fit): 0 -> 0, approaches 1") {
    OutputOptions o = opts(Tonemap::aces);
    CHECK(tonemap_pixel(Rgb(0.f), o) == Rgb(0.f));
    float at1 = tonemap_pixel(Rgb(1.f), o).x;
    CHECK(at1 == doctest::Approx(2.54 / 3.16).epsilon(1e-5).scale(1e-9));  // (2.51 + 0.03) / (2.43 + 0.59 + 0.14)
    CHECK(tonemap_pixel(Rgb(5.f), o).x > 0.98f);
    CHECK(tonemap_pixel(Rgb(5.f), o).x < 1.f);
    CHECK(tonemap_pixel(Rgb(1e6f), o).x == 1.f);
  }
  SUBCASE("exposure +1 stop doubles the input, for every operator") {
    for (Tonemap tm : {Tonemap::linear, Tonemap::reinhard, Tonemap::modified_reinhard, Tonemap::aces})
      for (float v : {0.01f, 0.2f, 0.45f, 1.3f, 7.f}) {
        Rgb x(v, 0.5f * v, 0.25f * v);
        CHECK(tonemap_pixel(x, opts(tm, 1.f)) == tonemap_pixel(x * 2.f, opts(tm, 0.f)));
        CHECK(tonemap_pixel(x, opts(tm, -2.f)) == tonemap_pixel(x * 0.25f, opts(tm, 0.f)));
      }
    CHECK(tonemap_pixel(Rgb(0.2f), opts(Tonemap::linear, 1.f)).x == doctest::Approx(0.4f));
  }
  SUBCASE("tonemap(Image) applies tonemap_pixel to every pixel") {
    Image img = gradient(5, 3);
    img.at(4, 2) = Rgb(9.f, 3.f, 0.1f);
    OutputOptions o = opts(Tonemap::aces, 0.5f, true);
    Image out = tonemap(img, o);
    REQUIRE(out.width == 5);
    REQUIRE(out.height == 3);
    for (size_t i = 0; i < img.pixels.size(); ++i) CHECK(out.pixels[i] == tonemap_pixel(img.pixels[i], o));
  }
}

// ---------------------------------------------------------------------------------------------
// Metrics

TEST_CASE("metrics: identical images, constant offsets, hand-computed relMSE") {
  Image ref = gradient(6, 4);
  CHECK(mse(ref, ref) == 0.0);
  CHECK(rel_mse(ref, ref) == 0.0);
  CHECK(mean_abs_error(ref, ref) == 0.0);

  for (float d : {0.5f, -0.25f, 3.f}) {
    Image test = ref;
    for (auto& p : test.pixels) p += Rgb(d);
    CHECK(mse(test, ref) == doctest::Approx(double(d) * d).epsilon(1e-5).scale(1e-9));
    CHECK(mean_abs_error(test, ref) == doctest::Approx(std::fabs(d)).epsilon(1e-5).scale(1e-9));
  }
  // Offset on one channel of one pixel only: the mean runs over pixels AND channels.
  Image one = ref;
  one.at(2, 1).y += 3.f;
  CHECK(mse(one, ref) == doctest::Approx(9.0 / (3 * 24)).epsilon(1e-5).scale(1e-9));

  // pbrt-v4 Image::MRSE: (t - r)^2 / (r + 0.01)^2, mean over pixels and channels.
  Image r2(2, 1), t2(2, 1);
  r2.at(0, 0) = Rgb(1.f, 0.f, 0.5f);
  t2.at(0, 0) = Rgb(1.5f, 0.1f, 0.5f);
  r2.at(1, 0) = Rgb(2.f, 4.f, 0.25f);
  t2.at(1, 0) = Rgb(2.f, 3.f, 0.f);
  double terms = 0.25 / (1.01 * 1.01) + 0.01 / (0.01 * 0.01) + 0.0 + 0.0 + 1.0 / (4.01 * 4.01) +
                 0.0625 / (0.26 * 0.26);
  CHECK(rel_mse(t2, r2) == doctest::Approx(terms / 6).epsilon(1e-6).scale(1e-9));
  // eps is a parameter: eps = 1 gives another known value.
  double terms1 = 0.25 / 4.0 + 0.01 / 1.0 + 1.0 / 25.0 + 0.0625 / (1.25 * 1.25);
  CHECK(rel_mse(t2, r2, 1.0) == doctest::Approx(terms1 / 6).epsilon(1e-6).scale(1e-9));
  // relMSE is not symmetric: the reference is the denominator.
  CHECK(rel_mse(r2, t2) != doctest::Approx(rel_mse(t2, r2)));
}

TEST_CASE("metrics reject size mismatch, non-finite input and empty images") {
  Image a(4, 3), b(3, 4);
  std::string msg = thrown_message([&] { mse(a, b); });
  CHECK(msg.find("4x3") != std::string::npos);
  CHECK(msg.find("3x4") != std::string::npos);
  CHECK_THROWS_AS(mse(a, b), std::invalid_argument);
  CHECK_THROWS_AS(rel_mse(a, b), std::invalid_argument);
  CHECK_THROWS_AS(mean_abs_error(a, b), std::invalid_argument);

  Image nan_img(4, 3);
  nan_img.at(2, 1).z = std::numeric_limits<float>::quiet_NaN();
  std::string m = thrown_message([&] { mse(nan_img, a); });
  CHECK(m.find("x=2, y=1") != std::string::npos);
  CHECK(m.find("test") != std::string::npos);
  CHECK_THROWS_AS(rel_mse(a, nan_img), std::invalid_argument);
  CHECK(thrown_message([&] { mean_abs_error(a, nan_img); }).find("reference") != std::string::npos);
  Image inf_img(4, 3);
  inf_img.at(0, 2).x = std::numeric_limits<float>::infinity();
  CHECK(thrown_message([&] { mse(inf_img, a); }).find("x=0, y=2") != std::string::npos);

  CHECK_THROWS_AS(mse(Image(), Image()), std::invalid_argument);
  CHECK_THROWS_AS(rel_mse(a, a, -1.0), std::invalid_argument);
}

TEST_CASE("image_stats counts NaN, inf and negative pixels and averages finite luminance") {
  Image img(4, 1, Rgb(1.f));
  img.at(0, 0) = Rgb(std::numeric_limits<float>::quiet_NaN(), 1.f, 1.f);
  img.at(1, 0) = Rgb(1.f, -std::numeric_limits<float>::infinity(), 1.f);
  img.at(2, 0) = Rgb(-1.f, 2.f, 0.f);
  ImageStats s = image_stats(img);
  CHECK(s.nan_count == 1);
  CHECK(s.inf_count == 1);
  CHECK(s.negative_count == 1);
  CHECK(s.mean_luminance == doctest::Approx((luminance(Rgb(-1.f, 2.f, 0.f)) + 1.0) / 2));
  CHECK(image_stats(Image(3, 3, Rgb(0.5f))).mean_luminance == doctest::Approx(0.5));
}


TEST_CASE("rel_mse over a mask: the mean over the masked pixels only; empty mask NaN; wrong size throws") {
  Image ref(4, 1), test(4, 1);
  for (int x = 0; x < 4; ++x) {
    ref.at(x, 0) = Rgb(1.0f);
    test.at(x, 0) = Rgb(x < 2 ? 1.0f : 2.0f);  // error only on pixels 2 and 3
  }
  const std::vector<uint8_t> left{1, 1, 0, 0}, right{0, 0, 1, 1}, none{0, 0, 0, 0}, short_mask{1, 1};
  const double per_pixel = 1.0 / (1.01 * 1.01);
  CHECK(rel_mse(test, ref, &left) == 0.0);
  CHECK(rel_mse(test, ref, &right) == doctest::Approx(per_pixel));
  CHECK(rel_mse(test, ref) == doctest::Approx(per_pixel / 2));
  CHECK(std::isnan(rel_mse(test, ref, &none)));
  CHECK_THROWS_AS(rel_mse(test, ref, &short_mask), std::invalid_argument);
}
TEST_CASE("rel_mse_lowpass: a uniform offset keeps its relMSE, white noise loses block^2 of it, blotches keep theirs") {
  const int w = 160, h = 96;  // 20 x 12 tiles of 8
  Image ref(w, h, Rgb(0.5f));
  Image offset = ref;
  for (Rgb& p : offset.pixels) p = p + Rgb(0.1f);
  CHECK(rel_mse_lowpass(offset, ref) == doctest::Approx(rel_mse(offset, ref)).epsilon(1e-5));
  CHECK(rel_mse_lowpass(offset, ref, 1) == rel_mse(offset, ref));
  std::mt19937 rng(17);
  std::normal_distribution<float> n(0.0f, 0.1f);
  Image noisy = ref, blotchy = ref;
  for (Rgb& p : noisy.pixels) p = p + Rgb(n(rng), n(rng), n(rng));
  // One draw per 8x8 tile: the same variance per pixel as `noisy`, correlated over the tile.
  std::vector<Rgb> tile(20 * 12);
  for (Rgb& t : tile) t = Rgb(n(rng), n(rng), n(rng));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) blotchy.at(x, y) = blotchy.at(x, y) + tile[size_t(y / 8) * 20 + size_t(x / 8)];
  const double full = rel_mse(noisy, ref), low = rel_mse_lowpass(noisy, ref);
  // 720 tile means of 64 independent pixels each: the ratio is 1/64 within sampling error (~5%).
  CHECK(low / full == doctest::Approx(1.0 / 64).epsilon(0.15));
  CHECK(rel_mse_lowpass(blotchy, ref) == doctest::Approx(rel_mse(blotchy, ref)).epsilon(1e-5));
  // Partial tiles: 9 x 9 pixels, block 8 (2 x 2 tiles), each a mean over the pixels it has.
  Image small(9, 9, Rgb(1.0f)), small_ref(9, 9, Rgb(1.0f));
  small.at(8, 8) = Rgb(2.0f);  // the 1x1 corner tile: its mean is the pixel
  CHECK(rel_mse_lowpass(small, small_ref) == doctest::Approx(1.0 / (1.01 * 1.01) / 4.0).epsilon(1e-6));
  CHECK_THROWS_AS(rel_mse_lowpass(small, small_ref, 0), std::invalid_argument);
}

}  // TEST_SUITE
