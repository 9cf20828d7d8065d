// pbrt-v4 "coateddiffuse" in the pbrt loader: parameters, defaults, textured reflectance, the coat
// tables prepared at load, and the warning for a medium in the layer (not modelled).
#include <fcntl.h>
#include <unistd.h>

#include <cstdio>

#include "loader_test_utils.h"
#include "scene/bsdf.h"
#include "scene/coated.h"
#include "scene/texture.h"

using namespace rl;
using namespace rl::loader_test;

namespace {

const char* kHead = "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 30\nWorldBegin\n";  // lines 1-3

// What load_text writes to stderr while loading `text` (the loader's warnings).
std::string load_warnings(const std::string& text, Scene& scene) {
  const fs::path log = temp_dir() / "stderr.txt";
  std::fflush(stderr);
  const int saved = ::dup(2), fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  REQUIRE(saved >= 0);
  REQUIRE(fd >= 0);
  ::dup2(fd, 2);
  ::close(fd);
  try {
    scene = load_text(text, "c.pbrt");
  } catch (...) {
    std::fflush(stderr);
    ::dup2(saved, 2);
    ::close(saved);
    throw;
  }
  std::fflush(stderr);
  ::dup2(saved, 2);
  ::close(saved);
  std::ifstream in(log);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

}  // namespace

TEST_SUITE("loaders") {

TEST_CASE("pbrt: coateddiffuse: defaults, parameters, textured reflectance, coat tables") {
  Scene s = load_text(std::string(kHead) +
                      "Material \"coateddiffuse\"\n"
                      "Material \"coateddiffuse\" \"rgb reflectance\" [0.8 0.2 0.1] \"float roughness\" 0.09 \"float eta\" 1.33\n"
                      "Material \"coateddiffuse\" \"float uroughness\" 0.1 \"float vroughness\" 0.3 \"bool remaproughness\" false "
                      "\"float thickness\" 0.02 \"integer maxdepth\" 5 \"integer nsamples\" 2 \"float g\" 0.3 \"rgb albedo\" [0 0 0]\n"
                      "Texture \"checks\" \"spectrum\" \"checkerboard\" \"float uscale\" 4 \"rgb tex1\" [1 0 0] \"rgb tex2\" [0 0 1]\n"
                      "Material \"coateddiffuse\" \"texture reflectance\" \"checks\" \"spectrum eta\" \"glass-BK7\"\n"
                      "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"point2 uv\" [0 0 1 0 0 1]\n");
  REQUIRE(s.materials.size() >= 4);
  const size_t n = s.materials.size();
  const Material &def = s.materials[n - 4], &rough = s.materials[n - 3], &aniso = s.materials[n - 2], &tex = s.materials.back();
  for (const Material* m : {&def, &rough, &aniso, &tex}) CHECK(m->type == Material::Type::coated_diffuse);
  // pbrt-v4's defaults: reflectance 0.5, eta 1.5, roughness 0 (a smooth coat).
  CHECK(near(def.reflectance, Vec3(0.5f)));
  CHECK(def.ior == doctest::Approx(1.5f));
  CHECK(def.alpha_x == 0);
  CHECK(def.coat_fdr == doctest::Approx(1 - (1 - fresnel_diffuse_reflectance(1.5)) / 2.25).epsilon(1e-5));
  CHECK(near(rough.reflectance, Vec3(0.8f, 0.2f, 0.1f)));
  CHECK(rough.ior == doctest::Approx(1.33f));
  CHECK(rough.alpha_x == doctest::Approx(0.3f));  // remapped: sqrt(0.09)
  CHECK(rough.coat_fdr == doctest::Approx(coat_internal_reflectance(1.33f, 0.3f)).epsilon(1e-6));
  CHECK(rough.coat_t[kCoatTableSize - 1] / 65535.0 == doctest::Approx(coat_transmittance(1.33f, 0.3f, 1.0)).epsilon(1e-4));
  CHECK(aniso.alpha_x == doctest::Approx(0.1f));
  CHECK(aniso.alpha_y == doctest::Approx(0.3f));
  CHECK(tex.ior == doctest::Approx(1.5168f));
  // Textured like diffuse: the texture's value at the hit reaches the Bsdf's base.
  REQUIRE(tex.reflectance_texture >= 0);
  CHECK(s.textures[size_t(tex.reflectance_texture)].kind == Texture::Kind::checkerboard);
  const Rgb r0 = material_reflectance(s, tex, Vec2{0.05f, 0.05f}), r1 = material_reflectance(s, tex, Vec2{0.3f, 0.05f});
  CHECK(near(r0, Vec3(1, 0, 0)) != near(r1, Vec3(1, 0, 0)));
  const Bsdf b = make_bsdf(tex, r0);
  CHECK(near(b.reflectance, r0));
  CHECK(bsdf_eval(b, Vec3{0, 0, 1}, Vec3{0, 0, 1}).x > 0);
}

TEST_CASE("pbrt: coateddiffuse: a medium in the layer (albedo) warns once, naming file:line") {
  Scene s;
  const std::string light = "LightSource \"point\" \"rgb I\" [1 1 1]\n";  // (a scene without light warns too)
  std::string w = load_warnings(std::string(kHead) + "Material \"coateddiffuse\" \"rgb albedo\" [0.5 0.5 0.5] \"float g\" 0.2\n" +
                                    "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]\n" + light,
                                s);
  CHECK(w.find("c.pbrt:4: warning: coateddiffuse: \"albedo\"") != std::string::npos);
  CHECK(w.find("warning", w.find("warning") + 1) == std::string::npos);  // one warning
  CHECK(s.materials.back().type == Material::Type::coated_diffuse);
  // albedo 0 (pbrt-v4's default) is the clear layer the model is: no warning.
  w = load_warnings(std::string(kHead) + "Material \"coateddiffuse\" \"rgb albedo\" [0 0 0]\n" + light, s);
  CHECK(w.find("warning") == std::string::npos);
  // Unknown parameters stay errors.
  CHECK(error_of(std::string(kHead) + "Material \"coateddiffuse\" \"float roughnes\" 0.1\n").find("roughnes") != std::string::npos);
}

}  // TEST_SUITE
