// restir export-mitsuba's mapping of coated diffuse (scene/mitsuba_export.h): Mitsuba's plastic for
// a smooth coat, roughplastic (ggx, the alpha, int_ior = eta) for a rough one, both nonlinear (the
// form of bsdf_coated.h) and two-sided; the base's reflectance as diffuse_reflectance.
#include <fstream>
#include <sstream>

#include "loader_test_utils.h"
#include "scene/mitsuba_export.h"

using namespace rl;
using namespace rl::loader_test;

TEST_SUITE("loaders") {

TEST_CASE("mitsuba export: coated diffuse as plastic / roughplastic with nonlinear") {
  const Scene s = load_text(
      "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 30\nWorldBegin\n"
      "LightSource \"infinite\" \"rgb L\" [1 1 1]\n"
      "Material \"coateddiffuse\" \"rgb reflectance\" [0.8 0.4 0.1] \"float eta\" 1.33\n"
      "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]\n"
      "Material \"coateddiffuse\" \"float roughness\" 0.09\n"
      "Shape \"trianglemesh\" \"point3 P\" [0 0 1 1 0 1 0 1 1]\n"
      "Material \"coateddiffuse\" \"float uroughness\" 0.04 \"float vroughness\" 0.16\n"
      "Shape \"trianglemesh\" \"point3 P\" [0 0 2 1 0 2 0 1 2]\n");
  const fs::path dir = temp_dir() / "mitsuba";
  MitsubaExportSettings settings;
  settings.camera = s.camera.keys[0];
  const std::vector<std::string> notes = export_mitsuba(s, settings, dir.string());
  std::ifstream in(dir / "scene.xml");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string xml = ss.str();
  CHECK(xml.find("<bsdf type=\"twosided\" id=\"mat1\"><bsdf type=\"plastic\"><float name=\"int_ior\" value=\"1.33000004\"/>"
                 "<float name=\"ext_ior\" value=\"1\"/><rgb name=\"diffuse_reflectance\" value=\"0.800000012, 0.400000006, "
                 "0.100000001\"/><boolean name=\"nonlinear\" value=\"true\"/></bsdf></bsdf>") != std::string::npos);
  CHECK(xml.find("<bsdf type=\"roughplastic\"><string name=\"distribution\" value=\"ggx\"/><float name=\"alpha\" "
                 "value=\"0.300000012\"/><float name=\"int_ior\" value=\"1.5\"/>") != std::string::npos);
  // Anisotropic: the mean alpha sqrt(0.2 * 0.4), with a note (roughplastic is isotropic).
  CHECK(xml.find("<float name=\"alpha\" value=\"0.28284") != std::string::npos);
  bool noted = false;
  for (const std::string& n : notes) noted |= n.find("anisotropic coat") != std::string::npos;
  CHECK(noted);
}

}  // TEST_SUITE
