// OBJ+MTL and glTF loaders (as whole scenes and as pbrt shapes), with files written by the tests.
#include "loader_test_utils.h"

using namespace rl;
using namespace rl::loader_test;

TEST_SUITE("loaders") {

TEST_CASE("obj: OBJ + MTL materials, emission, default camera; objmesh in pbrt") {
  fs::path d = temp_dir();
  write_file(d / "m.mtl",
             "newmtl red\nKd 0.8 0.1 0.1\n\nnewmtl lamp\nKd 0 0 0\nKe 5 4 3\n\n"
             "newmtl metal\nKd 0.1 0.1 0.1\nKs 0.9 0.8 0.7\nNs 198\n\nnewmtl glass\nKd 0 0 0\nNi 1.45\nd 0.2\n");
  std::string obj = write_file(d / "m.obj",
                               "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 2 0 0\n"
                               "o quad\nusemtl red\nf 1 2 3 4\n"
                               "o lamp\nusemtl lamp\nf 1 2 5\n"
                               "o shiny\nusemtl metal\nf 2 6 3\n"
                               "o clear\nusemtl glass\nf 1 3 5\n");
  Scene s = load_scene(obj);
  CHECK(s.triangle_count() == 5);
  REQUIRE(s.meshes.size() == 4);
  auto mat = [&](const std::string& src) -> const TriangleMesh& {
    for (const TriangleMesh& m : s.meshes)
      if (m.source.find(src) != std::string::npos) return m;
    FAIL("no mesh " << src);
    return s.meshes[0];
  };
  const TriangleMesh& quad = mat(":quad");
  CHECK(quad.triangle_count() == 2);
  CHECK(s.materials[size_t(quad.material)].name == "red");
  CHECK(near(s.materials[size_t(quad.material)].reflectance, Vec3(0.8f, 0.1f, 0.1f)));
  CHECK_FALSE(quad.emission);
  CHECK(near(resolved_normal(quad, 0), Vec3(0, 0, 1)));  // counter-clockwise = front
  const TriangleMesh& lamp = mat(":lamp");
  REQUIRE(lamp.emission);
  CHECK(near(lamp.emission->radiance, Vec3(5, 4, 3)));
  const Material& metal = s.materials[size_t(mat(":shiny").material)];
  CHECK(metal.type == Material::Type::conductor);
  CHECK(metal.use_reflectance);
  CHECK(metal.alpha_x == doctest::Approx(0.1));  // sqrt(2 / (198 + 2))
  const Material& glass = s.materials[size_t(mat(":clear").material)];
  CHECK(glass.type == Material::Type::dielectric);
  CHECK(glass.ior == doctest::Approx(1.45));
  REQUIRE(s.camera.keys.size() == 1);
  CHECK(s.camera.keys[0].fov_degrees == 45);
  Bounds3 b = s.bounds();
  Mat4 w = world_from_camera(s.camera.keys[0]);
  Vec3 eye = w.apply_point(Vec3(0));
  CHECK(near(eye, b.center() + Vec3(0, 0, 1.5f * 0.5f * length(b.diagonal()))));
  CHECK(near(normalize(w.apply_vector(Vec3(0, 0, 1))), Vec3(0, 0, -1)));
  CHECK(near(normalize(w.apply_vector(Vec3(1, 0, 0))), Vec3(1, 0, 0)));  // not mirrored

  // The project's objmesh extension: current material, transform and area light apply.
  Scene p = load_scene(write_file(d / "o.pbrt", kWorld +
                                                    "AttributeBegin AreaLightSource \"diffuse\" \"rgb L\" [2 2 2]\n"
                                                    "Material \"diffuse\" \"rgb reflectance\" [0.1 0.2 0.3]\n"
                                                    "Translate 0 10 0 Shape \"objmesh\" \"string filename\" \"m.obj\"\n"
                                                    "AttributeEnd\n"));
  CHECK(p.triangle_count() == 5);
  for (const TriangleMesh& m : p.meshes) {
    REQUIRE(m.emission);
    CHECK(near(m.emission->radiance, Vec3(2)));
    CHECK(near(p.materials[size_t(m.material)].reflectance, Vec3(0.1f, 0.2f, 0.3f)));
    for (const Vec3& q : m.positions) CHECK(q.y >= 10);
  }
  // map_Kd naming a missing file is an error naming the OBJ file.
  write_file(d / "t.mtl", "newmtl tex\nKd 1 1 1\nmap_Kd missing.png\n");
  std::string tobj = write_file(d / "t.obj", "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl tex\nf 1 2 3\n");
  try {
    load_scene(tobj);
    FAIL("no error");
  } catch (const SceneError& e) {
    CHECK(std::string(e.what()).find("missing.png") != std::string::npos);
  }
}

namespace {
std::string base64(const std::string& in) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    uint32_t v = uint32_t(uint8_t(in[i])) << 16 | uint32_t(uint8_t(in[i + 1])) << 8 | uint8_t(in[i + 2]);
    for (int k = 3; k >= 0; --k) out += t[(v >> (6 * k)) & 63];
  }
  if (i < in.size()) {
    uint32_t v = uint32_t(uint8_t(in[i])) << 16 | (i + 1 < in.size() ? uint32_t(uint8_t(in[i + 1])) << 8 : 0);
    out += t[(v >> 18) & 63];
    out += t[(v >> 12) & 63];
    out += i + 1 < in.size() ? t[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}
}  // namespace

TEST_CASE("gltf: embedded buffer, node transform, material, emission, camera") {
  // Two triangles (a quad in the xy plane) with u16 indices, translated by the node by (0, 0, -2).
  float pos[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
  std::string buf(reinterpret_cast<const char*>(pos), sizeof pos);
  buf.append(reinterpret_cast<const char*>(idx), sizeof idx);
  std::string json = R"({
  "asset": {"version": "2.0"},
  "scene": 0,
  "scenes": [{"nodes": [0, 1]}],
  "nodes": [{"mesh": 0, "translation": [0, 0, -2]},
            {"camera": 0, "translation": [0.5, 0.5, 3]}],
  "cameras": [{"type": "perspective", "perspective": {"yfov": 0.7853981634, "aspectRatio": 1.5, "znear": 0.1}}],
  "meshes": [{"name": "quad", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
  "materials": [{"name": "glow", "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 1], "metallicFactor": 0},
                 "emissiveFactor": [1, 0.5, 0.25]}],
  "buffers": [{"byteLength": 60, "uri": "data:application/octet-stream;base64,)" +
                     base64(buf) + R"("}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0,0,0], "max": [1,1,0]},
                {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}]
})";
  fs::path d = temp_dir();
  Scene s = load_scene(write_file(d / "q.gltf", json));
  CHECK(s.triangle_count() == 2);
  REQUIRE(s.meshes.size() == 1);
  const TriangleMesh& m = s.meshes[0];
  CHECK(near(m.positions[2], Vec3(1, 1, -2)));
  const Material& mat = s.materials[size_t(m.material)];
  CHECK(mat.name == "glow");
  CHECK(mat.type == Material::Type::diffuse);
  CHECK(near(mat.reflectance, Vec3(0.2f, 0.4f, 0.6f)));
  REQUIRE(m.emission);
  CHECK(near(m.emission->radiance, Vec3(1, 0.5f, 0.25f)));
  CHECK(near(resolved_normal(m, 0), Vec3(0, 0, 1)));
  REQUIRE(s.camera.keys.size() == 1);
  CHECK(s.camera.keys[0].fov_degrees == doctest::Approx(45));  // landscape: shorter axis = y
  const Mat4& cfw = s.camera.keys[0].camera_from_world;
  CHECK(near(cfw.apply_point(Vec3(0.5f, 0.5f, -2)), Vec3(0, 0, 5)));  // view direction -> +z
  CHECK(near(cfw.apply_vector(Vec3(1, 0, 0)), Vec3(1, 0, 0)));        // world +x on the right
  CHECK(near(cfw.apply_vector(Vec3(0, 1, 0)), Vec3(0, 1, 0)));
  // Broken JSON is a SceneError.
  CHECK_THROWS_AS(load_scene(write_file(d / "broken.gltf", "{\"asset\": ")), SceneError);
}


}  // TEST_SUITE
