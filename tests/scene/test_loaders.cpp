// Scene loaders: pbrt-v4 subset, PLY, OBJ+MTL, glTF. Real shared scenes plus small files written
// to a temp directory by the tests themselves.
#include "loader_test_utils.h"

using namespace rl;
using namespace rl::loader_test;

TEST_SUITE("loaders") {

TEST_CASE("pbrt: Cornell box") {
  Scene s = load_scene(RESTIR_SHARED_DIR "/scenes/cornell-box/scene-v4.pbrt");
  // floor, ceiling, back, right, left walls: 2 each; short and tall box: 12 each; light: 2.
  CHECK(s.triangle_count() == 5 * 2 + 12 + 12 + 2);
  CHECK(s.meshes.size() == 8);
  int emissive = 0;
  for (const TriangleMesh& m : s.meshes) {
    if (!m.emission) continue;
    ++emissive;
    CHECK(near(m.emission->radiance, Vec3(17, 12, 4)));
    CHECK_FALSE(m.emission->two_sided);
    CHECK(s.materials[size_t(m.material)].name == "Light");
    for (size_t t = 0; t < m.triangle_count(); ++t) CHECK(near(resolved_normal(m, t), Vec3(0, -1, 0)));
  }
  CHECK(emissive == 1);
  std::set<std::string> names;
  for (const Material& m : s.materials) names.insert(m.name);
  for (const char* n : {"LeftWall", "RightWall", "Floor", "Ceiling", "BackWall", "ShortBox", "TallBox", "Light"})
    CHECK(names.count(n) == 1);
  CHECK(s.materials[0].type == Material::Type::diffuse);
  CHECK(s.materials[0].reflectance.x == doctest::Approx(0.5));
  for (const Material& m : s.materials)
    if (m.name == "LeftWall") CHECK(near(m.reflectance, Vec3(0.63f, 0.065f, 0.05f)));
  REQUIRE(s.camera.keys.size() == 1);
  CHECK(s.camera.keys[0].fov_degrees == doctest::Approx(19.5));
  CHECK(s.hints.width == 1024);
  CHECK(s.hints.height == 1024);
  CHECK(s.hints.spp == 64);
  CHECK(s.hints.max_depth == 65);
  CHECK(s.hints.pixel_filter == "triangle");
  CHECK(s.hints.filter_radius == 1.0f);
  Bounds3 b = s.bounds();
  CHECK(near(b.lo, Vec3(-1, 0, -1), 1e-3f));
  CHECK(near(b.hi, Vec3(1, 2, 1), 1e-3f));
  Mat4 w = world_from_camera(s.camera.keys[0]);
  CHECK(near(w.apply_point(Vec3(0)), Vec3(0, 1, 6.8f)));
  CHECK(near(normalize(w.apply_vector(Vec3(0, 0, 1))), Vec3(0, 0, -1)));
  // Floor: its normal faces up (into the box), as the N given in the file.
  for (const TriangleMesh& m : s.meshes)
    if (s.materials[size_t(m.material)].name == "Floor") CHECK(near(resolved_normal(m, 0), Vec3(0, 1, 0)));
}

TEST_CASE("pbrt: Veach MIS") {
  Scene s = load_scene(RESTIR_SHARED_DIR "/scenes/veach-mis/scene-v4.pbrt");
  // This version of the scene has three emissive spheres (the original has four).
  REQUIRE(s.spheres.size() == 3);
  struct Expect {
    Vec3 c;
    float r, L;
  };
  Expect ex[] = {{{0, 6.5f, -2.8f}, 1, 7.599088f}, {{0, 6.5f, 0}, 0.5f, 30.396353f}, {{0, 6.5f, 2.7f}, 0.05f, 3039.6353f}};
  for (int i = 0; i < 3; ++i) {
    const Sphere& sp = s.spheres[size_t(i)];
    CHECK(near(sp.center, ex[i].c));
    CHECK(sp.radius == doctest::Approx(ex[i].r));
    REQUIRE(sp.emission);
    CHECK(sp.emission->radiance.x == doctest::Approx(ex[i].L));
    CHECK_FALSE(sp.flip_normal);
    CHECK(s.materials[size_t(sp.material)].name == "Null");
  }
  std::map<std::string, float> alpha = {{"Smooth", 0.01f}, {"Glossy", 0.05f}, {"Rough", 0.1f}, {"SuperRough", 0.25f}};
  int found = 0;
  for (const Material& m : s.materials)
    if (alpha.count(m.name)) {
      ++found;
      CHECK(m.type == Material::Type::conductor);
      CHECK(m.alpha_x == doctest::Approx(alpha[m.name]));  // remaproughness false: alpha = roughness
      CHECK(m.alpha_y == doctest::Approx(alpha[m.name]));
      CHECK(near(m.eta, Vec3(0.200438f, 0.924033f, 1.102212f)));
      CHECK(near(m.k, Vec3(3.912949f, 2.452848f, 2.142188f)));
    }
  CHECK(found == 4);
  CHECK(s.hints.width == 1280);
  CHECK(s.hints.height == 720);
  CHECK(s.hints.max_depth == 3);
  CHECK(s.camera.keys[0].fov_degrees == doctest::Approx(20.114292));
  Mat4 w = world_from_camera(s.camera.keys[0]);
  CHECK(near(w.apply_point(Vec3(0)), Vec3(28.2792f, 3.5f, 0), 1e-2f));
  CHECK(near(normalize(w.apply_vector(Vec3(0, 0, 1))), Vec3(-1, 0, 0)));
}

TEST_CASE("pbrt: furnace emits into the cube") {
  Scene s = load_scene(RESTIR_SHARED_DIR "/scenes/furnace.pbrt");
  CHECK(s.triangle_count() == 12);
  for (const TriangleMesh& m : s.meshes) {
    REQUIRE(m.emission);
    CHECK(near(m.emission->radiance, Vec3(1)));
    CHECK_FALSE(m.emission->two_sided);
    const Material& mat = s.materials[size_t(m.material)];
    CHECK(mat.type == Material::Type::diffuse);
    CHECK(near(mat.reflectance, Vec3(0.5f)));
    for (size_t t = 0; t < m.triangle_count(); ++t) {
      Vec3 c = (m.positions[m.indices[3 * t]] + m.positions[m.indices[3 * t + 1]] + m.positions[m.indices[3 * t + 2]]) / 3;
      CHECK(dot(resolved_normal(m, t), -c) > 0.5f);  // points toward the origin
    }
  }
  CHECK(s.hints.width == 64);
}

TEST_CASE("pbrt: transform order, column-major Transform, orientation flags") {
  auto world_p = [](const std::string& xf) {
    Scene s = load_text(kWorld + xf + "\nShape \"trianglemesh\" \"point3 P\" [1 0 0  0 1 0  0 0 1]\n");
    REQUIRE(s.meshes.size() == 1);
    return s.meshes[0].positions[0];
  };
  CHECK(near(world_p("Translate 1 2 3 Scale 2 2 2"), Vec3(3, 2, 3)));  // T * S * p
  CHECK(near(world_p("Scale 2 2 2 Translate 1 2 3"), Vec3(4, 4, 6)));  // S * T * p
  CHECK(near(world_p("Rotate 90 0 0 1"), Vec3(0, 1, 0)));
  CHECK(near(world_p("Transform [1 0 0 0  0 1 0 0  0 0 1 0  5 6 7 1]"), Vec3(6, 6, 7)));
  CHECK(near(world_p("Translate 1 0 0 ConcatTransform [2 0 0 0  0 2 0 0  0 0 2 0  0 0 0 1]"), Vec3(3, 0, 0)));
  CHECK(near(world_p("Translate 9 9 9 Identity"), Vec3(1, 0, 0)));
  CHECK(near(world_p("AttributeBegin Translate 5 0 0 AttributeEnd"), Vec3(1, 0, 0)));
  CHECK(near(world_p("CoordinateSystem \"a\" Translate 5 0 0 CoordSysTransform \"a\""), Vec3(1, 0, 0)));

  auto flip = [](const std::string& pre) {
    Scene s = load_text(kWorld + pre + "\nShape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0]\n");
    return s.meshes.at(0).flip_normal;
  };
  CHECK_FALSE(flip(""));
  CHECK(flip("ReverseOrientation"));
  CHECK(flip("Scale -1 1 1"));
  CHECK_FALSE(flip("ReverseOrientation Scale -1 1 1"));
  // With shading normals, the geometric normal agrees with N whatever the winding.
  Scene s = load_text(kWorld + "Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0] "
                               "\"normal N\" [0 0 -1 0 0 -1 0 0 -1]\n");
  CHECK(near(resolved_normal(s.meshes[0], 0), Vec3(0, 0, -1)));
  s = load_text(kWorld + "ReverseOrientation Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0] "
                         "\"normal N\" [0 0 -1 0 0 -1 0 0 -1]\n");
  CHECK(near(resolved_normal(s.meshes[0], 0), Vec3(0, 0, 1)));  // pbrt-v4 negates N too
  CHECK(near(s.meshes[0].normals[0], Vec3(0, 0, 1)));
}

TEST_CASE("pbrt: camera animation, lights, spheres, instances, materials") {
  Scene s = load_text(
      "ActiveTransform StartTime\nLookAt 0 0 5  0 0 0  0 1 0\nActiveTransform EndTime\nLookAt 0 0 7  0 0 0  0 1 0\n"
      "ActiveTransform All\nCamera \"perspective\" \"float fov\" 30\nWorldBegin\n"
      "LightSource \"point\" \"rgb I\" [1 2 3] \"float scale\" 2 \"point3 from\" [1 0 0]\n"
      "AttributeBegin Translate 0 0 1 LightSource \"infinite\" \"rgb L\" [0.5 0.5 0.5] AttributeEnd\n"
      "AttributeBegin AreaLightSource \"diffuse\" \"blackbody L\" 6500 \"float scale\" 3 \"bool twosided\" true\n"
      "  ReverseOrientation Translate 1 2 3 Scale 2 2 2 Shape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n"
      "ObjectBegin \"tri\" Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] ObjectEnd\n"
      "AttributeBegin Translate 10 0 0 ObjectInstance \"tri\" AttributeEnd\n"
      "AttributeBegin Translate 20 0 0 ObjectInstance \"tri\" AttributeEnd\n"
      "Material \"conductor\" \"spectrum eta\" \"metal-Au-eta\" \"spectrum k\" \"metal-Au-k\" \"float roughness\" 0.09\n"
      "Material \"dielectric\" \"float eta\" 1.33\n"
      "Material \"dielectric\" \"spectrum eta\" \"glass-BK7\"\n"
      "Texture \"checks\" \"spectrum\" \"checkerboard\" \"float uscale\" 4 \"rgb tex1\" [1 0 0] \"rgb tex2\" [0 0 1]\n"
      "Material \"diffuse\" \"texture reflectance\" \"checks\"\n"
      "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]\n");
  REQUIRE(s.camera.keys.size() == 2);
  CHECK(near(world_from_camera(s.camera.keys[0]).apply_point(Vec3(0)), Vec3(0, 0, 5)));
  CHECK(near(world_from_camera(s.camera.keys[1]).apply_point(Vec3(0)), Vec3(0, 0, 7)));
  CHECK(s.camera.keys[1].fov_degrees == 30);
  REQUIRE(s.point_lights.size() == 1);
  CHECK(near(s.point_lights[0].intensity, Vec3(2, 4, 6)));
  CHECK(near(s.point_lights[0].position, Vec3(1, 0, 0)));
  REQUIRE(s.environment);
  CHECK(s.environment->mapping == EnvironmentLight::Mapping::constant);
  CHECK(near(s.environment->radiance, Vec3(0.5f)));
  CHECK(near(s.environment->world_from_light.apply_point(Vec3(0)), Vec3(0, 0, 1)));
  CHECK(near(s.environment->light_from_world.apply_point(Vec3(0, 0, 1)), Vec3(0)));
  REQUIRE(s.spheres.size() == 1);
  CHECK(near(s.spheres[0].center, Vec3(1, 2, 3)));
  CHECK(s.spheres[0].radius == doctest::Approx(1));
  CHECK(s.spheres[0].flip_normal);
  REQUIRE(s.spheres[0].emission);
  CHECK(s.spheres[0].emission->two_sided);
  CHECK(luminance(s.spheres[0].emission->radiance) == doctest::Approx(3).epsilon(1e-3).scale(1e-9));
  CHECK(s.spheres[0].emission->radiance.x / s.spheres[0].emission->radiance.z == doctest::Approx(1).epsilon(0.1).scale(1e-9));
  REQUIRE(s.meshes.size() == 3);
  CHECK(near(s.meshes[0].positions[1], Vec3(11, 0, 0)));
  CHECK(near(s.meshes[1].positions[1], Vec3(21, 0, 0)));
  const Material& au = s.materials[s.materials.size() - 4];
  CHECK(au.type == Material::Type::conductor);
  CHECK(near(au.eta, Vec3(0.143119f, 0.374957f, 1.442479f)));
  CHECK(au.alpha_x == doctest::Approx(0.3));  // remaproughness default true: sqrt(0.09)
  CHECK(s.materials[s.materials.size() - 3].ior == doctest::Approx(1.33));
  CHECK(s.materials[s.materials.size() - 2].ior == doctest::Approx(1.5168));
  const Material& tm = s.materials.back();
  REQUIRE(tm.reflectance_texture >= 0);
  const Texture& tx = s.textures[size_t(tm.reflectance_texture)];
  CHECK(tx.kind == Texture::Kind::checkerboard);
  CHECK(tx.uscale == 4);
  CHECK(near(tx.tex1, Vec3(1, 0, 0)));
  CHECK(s.meshes[2].material == int(s.materials.size()) - 1);
}

TEST_CASE("ply: ascii and binary (little/big endian), quads triangulated") {
  fs::path d = temp_dir();
  // A unit quad (2 triangles) plus one triangle, with normals and uvs.
  float P[5][8] = {{0, 0, 0, 0, 0, 1, 0, 0}, {1, 0, 0, 0, 0, 1, 1, 0}, {1, 1, 0, 0, 0, 1, 1, 1},
                   {0, 1, 0, 0, 0, 1, 0, 1}, {2, 0, 0, 0, 0, 1, 0.5f, 0.5f}};
  std::string header_props =
      "element vertex 5\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\n"
      "property float nz\nproperty float u\nproperty float v\nelement face 2\nproperty list uchar int vertex_indices\n"
      "end_header\n";
  std::string ascii = "ply\nformat ascii 1.0\ncomment test\n" + header_props;
  for (auto& v : P) {
    for (float f : v) ascii += std::to_string(f) + " ";
    ascii += "\n";
  }
  ascii += "4 0 1 2 3\n3 1 4 2\n";
  auto binary = [&](bool big) {
    std::string b = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") + " 1.0\n" + header_props;
    auto put = [&](const void* src, size_t n) {
      char tmp[8];
      std::memcpy(tmp, src, n);
      if (big) std::reverse(tmp, tmp + n);  // the test machine is little endian
      b.append(tmp, n);
    };
    for (auto& v : P)
      for (float f : v) put(&f, 4);
    int faces[2][5] = {{4, 0, 1, 2, 3}, {3, 1, 4, 2, 0}};
    for (auto& f : faces) {
      unsigned char c = (unsigned char)f[0];
      b.push_back(char(c));
      for (int i = 1; i <= f[0]; ++i) put(&f[i], 4);
    }
    return b;
  };
  for (const auto& [name, text] : std::vector<std::pair<std::string, std::string>>{
           {"a.ply", ascii}, {"le.ply", binary(false)}, {"be.ply", binary(true)}}) {
    CAPTURE(name);
    PlyMesh m = read_ply(write_file(d / name, text));
    REQUIRE(m.positions.size() == 5);
    CHECK(m.indices == std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 1, 4, 2});
    CHECK(near(m.positions[4], Vec3(2, 0, 0)));
    REQUIRE(m.normals.size() == 5);
    CHECK(near(m.normals[2], Vec3(0, 0, 1)));
    REQUIRE(m.uvs.size() == 5);
    CHECK(m.uvs[2].x == 1);
    CHECK(m.uvs[4].y == 0.5f);
    Scene s = load_scene((d / name).string());
    CHECK(s.triangle_count() == 3);
    CHECK(s.camera.keys.size() == 1);
  }
  // As a pbrt plymesh, relative to the scene file, transformed.
  write_file(d / "scene.pbrt", kWorld + "Translate 0 0 5 Shape \"plymesh\" \"string filename\" \"le.ply\"\n");
  Scene s = load_scene((d / "scene.pbrt").string());
  REQUIRE(s.meshes.size() == 1);
  CHECK(near(s.meshes[0].positions[4], Vec3(2, 0, 5)));
  // Truncated binary data and bad indices are errors naming the file.
  std::string le = binary(false);
  CHECK_THROWS_AS(read_ply(write_file(d / "trunc.ply", le.substr(0, le.size() - 3))), SceneError);
  std::string bad = ascii;
  bad.replace(bad.find("3 1 4 2"), 7, "3 1 9 2");
  try {
    read_ply(write_file(d / "badidx.ply", bad));
    FAIL("no error");
  } catch (const SceneError& e) {
    CHECK(std::string(e.what()).find("badidx.ply:22:") != std::string::npos);
  }
}

TEST_CASE("pbrt: every bad input is a SceneError naming file and line") {
  struct Case {
    std::string text, expect;
  };
  const std::string tri = "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]\n";
  std::vector<Case> cases = {
      {kWorld + "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0\n", "bad.pbrt:3: unterminated '['"},
      {kWorld + "Material \"diffuse\" \"rgb reflectance [0.5 0.5 0.5]\n", "bad.pbrt:3: unterminated string"},
      {kWorld + "Material \"diffuse\" \"rgb reflectance\"\n", "bad.pbrt:3: missing value"},
      {kWorld + "AttributeBegin\n" + tri, "bad.pbrt:3: AttributeBegin not closed"},
      {kWorld + "\nFoo 1 2 3\n", "bad.pbrt:4: unknown directive 'Foo'"},
      {kWorld + "AttributeEnd\n", "bad.pbrt:3: AttributeEnd without a matching AttributeBegin"},
      {kWorld + "Shape \"plymesh\" \"string filename\" \"missing.ply\"\n", "bad.pbrt:3: plymesh: cannot open PLY file"},
      {kWorld + "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"nope.png\"\n",
       "bad.pbrt:3: cannot open image file"},
      {kWorld + "LightSource \"infinite\" \"string filename\" \"nope.exr\"\n", "bad.pbrt:3: cannot open image file"},
      {kWorld + "Material \"diffuse\" \"flot reflectance\" 0.5\n", "bad.pbrt:3: unknown parameter type 'flot'"},
      {kWorld + "Material \"diffuse\" \"float reflectance\" 0.5\n", "bad.pbrt:3: parameter \"float reflectance\": has type"},
      {kWorld + "Material \"diffuse\" \"rgb reflectance\" [0.5 0.5]\n", "bad.pbrt:3: parameter \"rgb reflectance\": expected 3"},
      {kWorld + "Scale 1 2 1 Shape \"sphere\"\n", "bad.pbrt:3: sphere: its transform must be"},
      {kWorld + "Shape \"sphere\" \"float zmax\" 0.5\n", "bad.pbrt:3: sphere: partial spheres"},
      {kWorld + "Material \"coatedconductor\"\n", "bad.pbrt:3: unsupported material 'coatedconductor'"},
      {kWorld + "Material \"interface\"\n", "bad.pbrt:3: unsupported material 'interface'"},
      {kWorld + "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\"\n", "bad.pbrt:3: unsupported directive 'MakeNamedMedium'"},
      {kWorld + "Material \"conductor\" \"spectrum eta\" \"metal-Xx-eta\"\n", "bad.pbrt:3: parameter \"spectrum eta\": unsupported named spectrum"},
      {kWorld + "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 5]\n",
       "bad.pbrt:3: parameter \"integer indices\": vertex index 5 is out of range"},
      {kWorld + "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 1]\n", "bad.pbrt:3: trianglemesh: \"integer indices\" required"},
      {kWorld + "Shape \"cylinder\"\n", "bad.pbrt:3: unsupported shape 'cylinder'"},
      {kWorld + "Shape \"sphere\" \"float radius\" 1 \"float alpha\" 0.5\n", "bad.pbrt:3: parameter \"float alpha\": unused"},
      {kWorld + "NamedMaterial \"nope\"\n", "bad.pbrt:3: NamedMaterial: unknown material 'nope'"},
      {"Camera \"perspective\"\n" + tri, "bad.pbrt:2: Shape is not allowed before WorldBegin"},
      {kWorld + "Camera \"perspective\"\n", "bad.pbrt:3: Camera is not allowed after WorldBegin"},
      {kWorld + "Include \"nothere.pbrt\"\n", "bad.pbrt:3: cannot open file"},
      {kWorld + "Translate 1 2\n", "bad.pbrt:"},
      {"Camera \"perspective\"\n", "bad.pbrt: no WorldBegin"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.text);
    std::string w = error_of(c.text);
    CHECK_MESSAGE(w.find(c.expect) != std::string::npos, w);
  }
  // An error inside an included file names that file and its line.
  fs::path d = temp_dir();
  write_file(d / "inc.pbrt", "\n\nBar\n");
  std::string main = write_file(d / "main.pbrt", kWorld + "Include \"inc.pbrt\"\n");
  try {
    load_scene(main);
    FAIL("no error");
  } catch (const SceneError& e) {
    CHECK(std::string(e.what()).find("inc.pbrt:3: unknown directive 'Bar'") != std::string::npos);
    CHECK(e.line() == 3);
  }
  CHECK_THROWS_AS(load_scene((d / "none.pbrt").string()), SceneError);
  CHECK_THROWS_AS(load_scene((d / "x.abc").string()), SceneError);
}

TEST_CASE("pbrt: Include is relative to the including file") {
  fs::path d = temp_dir();
  fs::create_directories(d / "sub");
  write_file(d / "sub" / "geo.pbrt", "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]\n");
  write_file(d / "sub" / "world.pbrt", "Include \"geo.pbrt\"\nImport \"geo.pbrt\"\n");
  Scene s = load_scene(write_file(d / "main.pbrt", kWorld + "Include \"sub/world.pbrt\"\n"));
  CHECK(s.triangle_count() == 2);
  CHECK(s.meshes[0].source.find("geo.pbrt:1") != std::string::npos);
}

TEST_CASE("pbrt: blackbody and named spectra helpers") {
  Rgb w = pbrt::blackbody_rgb(6500);
  CHECK(luminance(w) == doctest::Approx(1).epsilon(1e-4).scale(1e-9));
  CHECK(w.x == doctest::Approx(1).epsilon(0.1).scale(1e-9));
  CHECK(w.z == doctest::Approx(1).epsilon(0.1).scale(1e-9));
  Rgb warm = pbrt::blackbody_rgb(2700);
  CHECK(warm.x > warm.z * 2);
  CHECK(pbrt::named_spectrum_rgb("metal-Ag-k").has_value());
  CHECK_FALSE(pbrt::named_spectrum_rgb("metal-Zz-k").has_value());
}

}  // TEST_SUITE

TEST_SUITE("loaders") {
TEST_CASE("pbrt: image textures and environment maps through the image module") {
  fs::path d = temp_dir();
  Image sq(4, 4, Rgb(0.25f)), wide(8, 4, Rgb(2)), odd(9, 3, Rgb(1));
  sq.at(0, 0) = Rgb(1, 0, 0);
  write_exr((d / "sq.exr").string(), sq);
  write_exr((d / "wide.exr").string(), wide);
  write_exr((d / "odd.exr").string(), odd);
  Scene s = load_scene(write_file(d / "a.pbrt", kWorld +
      "Rotate 90 1 0 0 LightSource \"infinite\" \"string filename\" \"sq.exr\" \"float scale\" 3\n"
      "Texture \"img\" \"spectrum\" \"imagemap\" \"string filename\" \"wide.exr\" \"float scale\" 0.5 \"float uscale\" 2\n"
      "Material \"diffuse\" \"texture reflectance\" \"img\"\n"
      "Texture \"s\" \"spectrum\" \"scale\" \"texture tex\" \"img\" \"float scale\" 2\n"));
  REQUIRE(s.environment);
  CHECK(s.environment->mapping == EnvironmentLight::Mapping::equal_area);
  CHECK(near(s.environment->radiance, Vec3(3)));
  CHECK(s.environment->image.width == 4);
  CHECK(near(s.environment->image.at(0, 0), Vec3(1, 0, 0)));
  CHECK(near(s.environment->world_from_light.apply_vector(Vec3(0, 1, 0)), Vec3(0, 0, 1)));
  REQUIRE(s.textures.size() == 2);
  CHECK(s.textures[0].kind == Texture::Kind::image);
  CHECK(s.textures[0].uscale == 2);
  CHECK(near(s.textures[0].image.at(3, 2), Vec3(1)));  // 2 * scale 0.5
  CHECK(near(s.textures[1].image.at(3, 2), Vec3(2)));  // scale texture: 2 * 1
  CHECK(s.materials.back().reflectance_texture == 0);
  Scene e = load_scene(write_file(d / "b.pbrt", kWorld + "LightSource \"infinite\" \"string filename\" \"wide.exr\"\n"));
  CHECK(e.environment->mapping == EnvironmentLight::Mapping::equirect);
  std::string w = error_of(kWorld + "\nLightSource \"infinite\" \"string filename\" \"" + (d / "odd.exr").string() + "\"\n");
  CHECK(w.find("bad.pbrt:4: infinite light: image") != std::string::npos);
  w = error_of(kWorld + "LightSource \"infinite\" \"rgb L\" [1 1 1] \"string filename\" \"" + (d / "sq.exr").string() + "\"\n");
  CHECK(w.find("bad.pbrt:3:") != std::string::npos);
  // A file that exists but is not an image: the image module's error, with our file:line.
  write_file(d / "junk.exr", "not an exr");
  w = error_of(kWorld + "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"" + (d / "junk.exr").string() + "\"\n");
  CHECK(w.find("bad.pbrt:3: cannot read image") != std::string::npos);
}
}  // TEST_SUITE

TEST_SUITE("loaders") {
TEST_CASE("pbrt and ply: every truncation of a valid file loads or throws SceneError, never anything else") {
  fs::path d = temp_dir();
  std::ifstream in(RESTIR_SHARED_DIR "/scenes/cornell-box/scene-v4.pbrt");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  REQUIRE(text.size() > 1000);
  int errors = 0, loaded = 0;
  for (size_t n = 0; n < text.size(); n += 97) {
    std::string path = write_file(d / "cut.pbrt", text.substr(0, n));
    try {
      load_scene(path);
      ++loaded;
    } catch (const SceneError& e) {
      ++errors;
      CHECK(std::string(e.what()).find("cut.pbrt") != std::string::npos);
    }
  }
  CHECK(errors > 0);
  std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
                    "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  CHECK_THROWS_AS(read_ply(write_file(d / "huge.ply", ply)), SceneError);
  CHECK_THROWS_AS(read_ply(write_file(d / "empty.ply", "")), SceneError);
  CHECK_THROWS_AS(read_ply((d / "absent.ply").string()), SceneError);
}
}  // TEST_SUITE
