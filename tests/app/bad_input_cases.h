// The table of hostile inputs run by test_bad_input.cpp. Each case: files to create in a fresh
// folder, the restir arguments ("{d}" = that folder), the exit status, and substrings the one
// "error:" line must contain (file:line, the parameter's name).
#pragma once
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "image/image_io.h"

struct BadCase {
  std::string name;
  std::vector<std::pair<std::string, std::string>> files;  // name -> contents ("dir/" = a folder)
  std::string args;
  int status = 1;
  std::vector<std::string> expect;
};

inline std::string good_scene() {
  return "Film \"rgb\" \"integer xresolution\" [8] \"integer yresolution\" [8]\n"  // line 1
         "Camera \"perspective\" \"float fov\" [60]\n"                             // line 2
         "WorldBegin\n"                                                           // line 3
         "AttributeBegin\n"                                                       // line 4
         "AreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\n"                        // line 5
         "Shape \"trianglemesh\" \"point3 P\" [-1 -1 5  1 -1 5  1 1 5  -1 1 5] \"integer indices\" [0 1 2 0 2 3]\n"
         "AttributeEnd\n";                                                        // line 7
}

namespace bad_input_detail {

inline std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (size_t at = 0; (at = s.find(from, at)) != std::string::npos; at += to.size()) s.replace(at, from.size(), to);
  return s;
}

// The good scene with `line` added as line 8 (in the world block).
inline std::string world_line(const std::string& line) { return good_scene() + line + "\n"; }
// A scene whose line 1 is `line` (Film replaces the good scene's Film, Camera goes on line 2 in
// place of its Camera; other directives are put before the good scene's).
inline std::string header_line(const std::string& line) {
  std::string g = good_scene();
  size_t l1 = g.find('\n') + 1, l2 = g.find('\n', l1) + 1;
  if (line.starts_with("Film")) return line + "\n" + g.substr(l1);
  if (line.starts_with("Camera")) return g.substr(0, l1) + line + "\n" + g.substr(l2);
  return line + "\n" + g;
}

// A valid 2x2 PNG (for a texture that must load).
inline std::string tiny_png() {
  std::string path = std::filesystem::temp_directory_path() / ("restir-bad-tex-" + std::to_string(::getpid()) + ".png");
  rl::write_png(path, rl::Image(2, 2, rl::Rgb(0.5f)));
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::filesystem::remove(path);
  return bytes;
}

inline const char* kRender = "render -q --spp 1 {d}/s.pbrt -o {d}/o.exr";

}  // namespace bad_input_detail

inline std::vector<BadCase> bad_input_cases() {
  using namespace bad_input_detail;
  std::vector<BadCase> v;
  // A parameter template with V for the value, each bad value, the line the scene puts it on.
  struct Param {
    std::string line;  // with V
    std::vector<std::string> bad;
    std::string param;  // expected in the message
    bool header = false;
  };
  const std::vector<Param> params = {
      // Lights: L, I, scale >= 0 and finite.
      {"AreaLightSource \"diffuse\" \"rgb L\" [V 1 1]", {"nan", "inf", "-inf", "1e39", "-1", "-1e-3"}, "\"rgb L\""},
      {"AreaLightSource \"diffuse\" \"float scale\" [V]", {"nan", "inf", "-2", "1e300"}, "\"float scale\""},
      {"AreaLightSource \"diffuse\" \"blackbody L\" [V]", {"nan", "-100", "0"}, "L"},
      {"LightSource \"point\" \"rgb I\" [V 1 1]", {"nan", "inf", "-1"}, "\"rgb I\""},
      {"LightSource \"point\" \"float scale\" [V]", {"nan", "-1", "-inf"}, "\"float scale\""},
      {"LightSource \"point\" \"point3 from\" [V 0 0]", {"nan", "inf", "1e39", "1e30"}, "from"},
      {"LightSource \"infinite\" \"rgb L\" [V 1 1]", {"nan", "-1", "inf"}, "\"rgb L\""},
      {"LightSource \"infinite\" \"float scale\" [V]", {"nan", "-0.5"}, "\"float scale\""},
      {"LightSource \"point\" \"spectrum I\" [V]", {"nan", "-3"}, "\"spectrum I\""},
      // Spot: a cone in (0, 180], a falloff band in [0, coneangle] (default coneangle 30), from != to.
      {"LightSource \"spot\" \"float coneangle\" [V]", {"0", "-10", "180.5", "1e39", "nan"}, "\"float coneangle\""},
      {"LightSource \"spot\" \"float conedeltaangle\" [V]", {"-1", "30.5", "nan"}, "\"float conedeltaangle\""},
      {"LightSource \"spot\" \"float coneangle\" 10 \"float conedeltaangle\" [V]", {"11", "90"}, "\"float conedeltaangle\""},
      {"LightSource \"spot\" \"rgb I\" [V 1 1]", {"nan", "inf", "-1"}, "\"rgb I\""},
      {"LightSource \"spot\" \"point3 to\" [V 0 0]", {"nan", "1e30"}, "\"point3 to\""},
      {"LightSource \"spot\" \"point3 from\" [0 0 V]", {"1"}, "\"point3 from\""},  // the default "to"
      // Distant: from != to, L >= 0, illuminance > 0.
      {"LightSource \"distant\" \"point3 to\" [0 0 V]", {"0"}, "\"point3 to\""},
      {"LightSource \"distant\" \"point3 from\" [1 2 3] \"point3 to\" [1 2 V]", {"3"}, "\"point3 to\""},
      {"LightSource \"distant\" \"rgb L\" [V 1 1]", {"nan", "-1", "inf"}, "\"rgb L\""},
      {"LightSource \"distant\" \"float illuminance\" [V]", {"0", "-1", "nan"}, "\"float illuminance\""},
      // Materials: reflectance in [0, 1], eta > 0, k >= 0, roughness >= 0.
      {"Material \"diffuse\" \"rgb reflectance\" [V 0.5 0.5]", {"nan", "inf", "-0.1", "1.5", "1e39"}, "\"rgb reflectance\""},
      {"Material \"diffuse\" \"spectrum reflectance\" [V]", {"2", "-1"}, "\"spectrum reflectance\""},
      {"Material \"conductor\" \"rgb reflectance\" [V 1 1]", {"-1", "2", "nan"}, "\"rgb reflectance\""},
      {"Material \"conductor\" \"rgb k\" [V 1 1]", {"nan", "-1", "inf"}, "\"rgb k\""},
      {"Material \"conductor\" \"rgb eta\" [V 1 1]", {"0", "-1", "nan"}, "\"rgb eta\""},
      {"Material \"conductor\" \"float roughness\" [V]", {"nan", "inf", "-1"}, "\"float roughness\""},
      {"Material \"conductor\" \"float uroughness\" [V]", {"-0.1", "nan"}, "\"float uroughness\""},
      {"Material \"conductor\" \"float vroughness\" [V]", {"-0.1", "inf"}, "\"float vroughness\""},
      {"Material \"dielectric\" \"float eta\" [V]", {"0", "-1.5", "nan", "inf"}, "\"float eta\""},
      {"Material \"dielectric\" \"float roughness\" [V]", {"-1", "nan"}, "\"float roughness\""},
      {"MakeNamedMaterial \"m\" \"string type\" \"diffuse\" \"rgb reflectance\" [V 0 0]", {"-1", "nan"}, "\"rgb reflectance\""},
      {"Material \"coateddiffuse\" \"rgb reflectance\" [V 0.5 0.5]", {"nan", "-0.1", "1.5"}, "\"rgb reflectance\""},
      {"Material \"coateddiffuse\" \"float eta\" [V]", {"0", "-1.5", "nan", "inf"}, "\"float eta\""},
      {"Material \"coateddiffuse\" \"float roughness\" [V]", {"-1", "nan", "inf"}, "\"float roughness\""},
      {"Material \"coateddiffuse\" \"float vroughness\" [V]", {"-0.1"}, "\"float vroughness\""},
      {"Material \"coateddiffuse\" \"float thickness\" [V]", {"0", "-0.01", "nan"}, "\"float thickness\""},
      {"Material \"coateddiffuse\" \"rgb albedo\" [V 0 0]", {"-1", "2", "nan"}, "\"rgb albedo\""},
      {"Material \"coateddiffuse\" \"float g\" [V]", {"-2", "1.5", "nan"}, "\"float g\""},
      {"Material \"coateddiffuse\" \"integer maxdepth\" [V]", {"0", "-3"}, "\"integer maxdepth\""},
      {"Material \"coateddiffuse\" \"integer nsamples\" [V]", {"0"}, "\"integer nsamples\""},
      // Textures: finite scales, non-negative values.
      {"Texture \"t\" \"spectrum\" \"checkerboard\" \"float uscale\" [V]", {"nan", "inf", "0"}, "\"float uscale\""},
      {"Texture \"t\" \"spectrum\" \"checkerboard\" \"float vscale\" [V]", {"nan", "-inf", "0"}, "\"float vscale\""},
      {"Texture \"t\" \"spectrum\" \"checkerboard\" \"float udelta\" [V]", {"nan"}, "\"float udelta\""},
      {"Texture \"t\" \"spectrum\" \"scale\" \"float scale\" [V]", {"-1", "nan", "inf"}, "\"float scale\""},
      {"Texture \"t\" \"spectrum\" \"checkerboard\" \"rgb tex1\" [V 1 1]", {"nan", "-1"}, "\"rgb tex1\""},
      {"Texture \"t\" \"spectrum\" \"constant\" \"rgb value\" [V 1 1]", {"nan", "-1", "inf"}, "\"rgb value\""},
      {"Texture \"t\" \"spectrum\" \"scale\" \"float scale\" [V]", {"nan", "inf"}, "\"float scale\""},
      // Shapes.
      {"Shape \"sphere\" \"float radius\" [V]", {"0", "-1", "nan", "inf", "1e39", "1e30"}, "radius"},
      {"Shape \"sphere\" \"float zmin\" [V]", {"nan"}, "\"float zmin\""},
      {"Shape \"trianglemesh\" \"point3 P\" [V 0 0 1 0 0 0 1 0]", {"nan", "inf", "-inf", "1e39"}, "\"point3 P\""},
      {"Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 V]",
       {"-1", "3", "1e10", "1.5", "nan"}, "indices"},
      {"Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"normal N\" [V 0 1 0 0 1 0 0 1]", {"nan", "inf"}, "\"normal N\""},
      {"Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"point2 uv\" [V 0 1 0 0 1]", {"nan", "inf"}, "\"point2 uv\""},
      // Transforms (directive arguments).
      {"Translate V 0 0", {"nan", "inf", "1e39", "x"}, "Translate"},
      {"Scale V 1 1", {"0", "nan", "inf", "1e39"}, "Scale"},
      {"Rotate V 0 1 0", {"nan", "inf"}, "Rotate"},
      {"Transform [V 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1]", {"nan", "0", "inf"}, "Transform"},
      {"ConcatTransform [1 0 0 0  0 1 0 0  0 0 1 0  V 0 0 1]", {"nan", "inf"}, "ConcatTransform"},
      // Render settings, before WorldBegin: out of range and non-integers, with the parameter's name.
      {"Film \"rgb\" \"integer xresolution\" [V]", {"0", "-5", "2000000000", "1e10", "1.5", "nan"}, "xresolution", true},
      {"Sampler \"zsobol\" \"integer pixelsamples\" [V]", {"0", "-1", "nan", "1e20"}, "pixelsamples", true},
      {"Integrator \"path\" \"integer maxdepth\" [V]", {"-1", "1e10", "nan", "5000"}, "maxdepth", true},
      {"PixelFilter \"gaussian\" \"float xradius\" [V]", {"0", "-1", "nan", "100"}, "xradius", true},
      {"Camera \"perspective\" \"float fov\" [V]", {"0", "180", "nan", "-10", "1e39"}, "fov", true},
      {"LookAt V 0 0  0 0 1  0 1 0", {"nan", "inf", "1e30"}, "", true},
  };
  for (const Param& p : params)
    for (const std::string& b : p.bad) {
      std::string line = replace_all(p.line, "V", b);
      std::string text = p.header ? header_line(line) : world_line(line);
      std::string where = p.header ? (p.line.starts_with("Camera") ? "s.pbrt:2" : "s.pbrt:1") : "s.pbrt:8";
      BadCase c{p.line + " with " + b, {{"s.pbrt", text}}, kRender, 1, {where}};
      if (!p.param.empty()) c.expect.push_back(p.param);
      v.push_back(c);
    }

  // A spot cone cannot follow a non-uniform scale (pbrt-v4's would turn elliptical).
  v.push_back({"spot under a non-uniform scale", {{"s.pbrt", world_line("Scale 1 2 1\nLightSource \"spot\"")}}, kRender, 1,
               {"s.pbrt:9", "spot light", "uniform scale"}});

  // Geometry that is finite per value but absurd in the world (Embree crashed on these).
  v.push_back({"Scale 1e30 on a mesh", {{"s.pbrt", world_line("Scale 1e30 1e30 1e30\nShape \"trianglemesh\" \"point3 P\" "
                                                               "[0 0 0 1 0 0 0 1 0]")}},
               kRender, 1, {"s.pbrt:8", "Scale"}});
  v.push_back({"Scale 1e12 puts a mesh beyond the world", {{"s.pbrt", world_line("Scale 1e12 1e12 1e12\nShape \"trianglemesh\" "
                                                                                   "\"point3 P\" [0 0 0 2 0 0 0 2 0]")}},
               kRender, 1, {"s.pbrt:9", "vertex"}});
  v.push_back({"vertices at 1e30", {{"s.pbrt", world_line("Shape \"trianglemesh\" \"point3 P\" [1e30 0 0 -1e30 0 0 0 1e30 0]")}},
               kRender, 1, {"s.pbrt:8", "vertex"}});
  v.push_back({"Scale overflow in the CTM", {{"s.pbrt", world_line("Scale 1e30 1 1\nScale 1e30 1 1")}}, kRender, 1,
               {"s.pbrt:9", "Scale"}});
  // Animation files (issue 11): Attribute "shape"/"light" "string animation" FILE.
  auto anim = [&](const std::string& name, const std::string& json, std::vector<std::string> expect) {
    v.push_back({name, {{"a.json", json}, {"s.pbrt", world_line("Attribute \"shape\" \"string animation\" \"a.json\"")}},
                 kRender, 1, std::move(expect)});
  };
  anim("animation: frames not increasing", R"({"keys": [{"frame": 3}, {"frame": 3}]})", {"s.pbrt:8", "a.json", "keys[1].frame"});
  anim("animation: translate 1e300", R"({"keys": [{"frame": 0, "translate": [1e300, 0, 0]}]})", {"s.pbrt:8", "a.json", "translate"});
  anim("animation: rotation about a zero axis", R"({"keys": [{"frame": 0, "rotate": [30, 0, 0, 0]}]})", {"a.json", "rotate"});
  anim("animation: negative intensity", R"({"keys": [{"frame": 0, "intensity": -1}]})", {"a.json", "intensity"});
  anim("animation: unknown key", R"({"keys": [{"frame": 0, "spin": 1}]})", {"a.json", "spin"});
  anim("animation: no keys", R"({"keys": []})", {"a.json", "keys"});
  anim("animation: invalid JSON", R"({"keys": [)", {"a.json", "JSON"});
  anim("animation: negative frame", R"({"keys": [{"frame": -2}]})", {"a.json", "frame"});
  v.push_back({"animation file missing", {{"s.pbrt", world_line("Attribute \"shape\" \"string animation\" \"none.json\"")}},
               kRender, 1, {"s.pbrt:8", "none.json"}});
  v.push_back({"animation of a material", {{"a.json", R"({"keys": [{"frame": 0}]})"},
                                           {"s.pbrt", world_line("Attribute \"material\" \"string animation\" \"a.json\"")}},
               kRender, 1, {"s.pbrt:8", "animation"}});
  v.push_back({"Rotate about a zero axis", {{"s.pbrt", world_line("Rotate 30 0 0 0")}}, kRender, 1, {"s.pbrt:8", "Rotate"}});
  v.push_back({"LookAt degenerate", {{"s.pbrt", header_line("LookAt 0 0 0  0 0 0  0 1 0")}}, kRender, 1, {"s.pbrt:1", "LookAt"}});
  v.push_back({"singular Transform", {{"s.pbrt", world_line("Transform [0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0]")}}, kRender, 1,
               {"s.pbrt:8", "Transform"}});
  v.push_back({"mesh without triangles", {{"s.pbrt", world_line("Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 1]")}},
               kRender, 1, {"s.pbrt:8", "indices"}});

  // Files: includes, meshes, images, garbage.
  v.push_back({"Include of a directory", {{"s.pbrt", world_line("Include \"sub\"")}, {"sub/", ""}}, kRender, 1,
               {"s.pbrt:8", "directory"}});
  v.push_back({"Include of a missing file", {{"s.pbrt", world_line("Include \"nope.pbrt\"")}}, kRender, 1, {"s.pbrt:8", "nope.pbrt"}});
  v.push_back({"recursive Include", {{"s.pbrt", world_line("Include \"r.pbrt\"")}, {"r.pbrt", "Include \"r.pbrt\"\n"}},
               kRender, 1, {"r.pbrt:1", "Include"}});
  v.push_back({"camera position beyond the world", {{"s.pbrt", header_line("Translate 1e13 0 0")}}, kRender, 1,
               {"s.pbrt:3", "Camera"}});
  v.push_back({"bad value inside an included file", {{"s.pbrt", world_line("Include \"inc.pbrt\"")},
                                                      {"inc.pbrt", "\nMaterial \"diffuse\" \"rgb reflectance\" [2 0 0]\n"}},
               kRender, 1, {"inc.pbrt:2", "reflectance"}});
  v.push_back({"binary bytes as a pbrt scene", {{"s.pbrt", std::string("WorldBegin\n\x01\x02\0\xff\xfe", 17)}}, kRender, 1,
               {"s.pbrt:2"}});
  v.push_back({"random bytes as OBJ", {{"m.obj", "\x13\x37 garbage \xff\n\x01\x02\x03\n"}}, "render -q {d}/m.obj -o {d}/o.exr", 1,
               {"m.obj", "no triangles"}});
  // Found by fuzz_obj (fuzz/regressions/obj-index-overflow.obj): 3 * index overflowed an int (UBSan).
  v.push_back({"OBJ with an index of -3333333331 (fuzz)", {{"m.obj", std::string("\x76\xf2\x30\x20\x30\x20\x30\x0a\xf6\x20\x31\xff\xff\xff\xff\xff\x20\x31\x6d\x74\x6c\x6c\x20\x31\x20\x30\x20\x31\x0a\x76\x20\x31\x31\x20\x30\x20\x31\x0a\x76\x20\x30\x20\x31\x20\x31\x0a\x66\x20\x2d\x33\x33\x33\x33\x33\x33\x33\x33\x33\x31\x20\x2d\x32\x20\x2d\x33\x0a", 66)}},
               "render -q {d}/m.obj -o {d}/o.exr", 1, {"m.obj", "index"}});
  v.push_back({"OBJ with a non-numeric coordinate", {{"m.obj", "v 0 0 0\nv 1 abc 0\nv 0 1 0\nf 1 2 3\n"}},
               "render -q {d}/m.obj -o {d}/o.exr", 1, {"m.obj:2", "'abc' is not a finite number"}});
  v.push_back({"OBJ with a short vertex line", {{"m.obj", "v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n"}},
               "render -q {d}/m.obj -o {d}/o.exr", 1, {"m.obj:2", "expected 3"}});
  v.push_back({"objmesh with a non-numeric coordinate", {{"s.pbrt", world_line("Shape \"objmesh\" \"string filename\" \"m.obj\"")},
                                                        {"m.obj", "v 0 0 0\nv 1 0 0\nv 0 x1 0\nf 1 2 3\n"}},
               kRender, 1, {"m.obj:3", "'x1'"}});
  v.push_back({"glTF 1.0", {{"m.gltf", R"({"asset": {"version": "1.0"}, "meshes": {"m": {"primitives": []}}})"}},
               "render -q {d}/m.gltf -o {d}/o.exr", 1, {"m.gltf", "glTF 1.0 is not supported", "2.0"}});
  v.push_back({"empty OBJ", {{"m.obj", ""}}, "render -q {d}/m.obj -o {d}/o.exr", 1, {"m.obj", "no triangles"}});
  v.push_back({"OBJ with an overflowing vertex", {{"m.obj", "v 1e39 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"}}, "render -q {d}/m.obj -o {d}/o.exr",
               1, {"m.obj", "vertex"}});
  v.push_back({"OBJ with a vertex at 1e30", {{"m.obj", "v 1e30 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"}},
               "render -q {d}/m.obj -o {d}/o.exr", 1, {"m.obj", "vertex"}});
  v.push_back({"glTF without meshes", {{"m.gltf", R"({"asset": {"version": "2.0"}})"}}, "render -q {d}/m.gltf -o {d}/o.exr", 1,
               {"m.gltf", "no triangles"}});
  v.push_back({"glTF that is not JSON", {{"m.gltf", "not json at all"}}, "render -q {d}/m.gltf -o {d}/o.exr", 1, {"m.gltf"}});
  // glTF values: the file is named, with what is wrong.
  v.push_back({"glTF node translated to 1e39", {{"m.gltf", R"GLTF({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0,1]}],"nodes":[{"mesh":0,"translation":[1e+39,0,0]},{"camera":0,"translation":[0,0,3]}],"cameras":[{"type":"perspective","perspective":{"yfov":0.8,"znear":0.01}}],"materials":[{"pbrMetallicRoughness":{"baseColorFactor":[0.8,0.2,0.2,1],"metallicFactor":0,"roughnessFactor":0.5},"emissiveFactor":[1,1,1]}],"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,"material":0}]}],"buffers":[{"byteLength":44,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA="}],"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}]})GLTF"}},
               "render -q {d}/m.gltf -o {d}/o.exr", 1, {"m.gltf", "vertex"}});
  v.push_back({"glTF base colour 2", {{"m.gltf", R"GLTF({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0,1]}],"nodes":[{"mesh":0,"translation":[0,0,-1]},{"camera":0,"translation":[0,0,3]}],"cameras":[{"type":"perspective","perspective":{"yfov":0.8,"znear":0.01}}],"materials":[{"pbrMetallicRoughness":{"baseColorFactor":[2,0,0,1],"metallicFactor":0,"roughnessFactor":0.5},"emissiveFactor":[1,1,1]}],"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,"material":0}]}],"buffers":[{"byteLength":44,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA="}],"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}]})GLTF"}},
               "render -q {d}/m.gltf -o {d}/o.exr", 1, {"m.gltf", "reflectance"}});
  v.push_back({"glTF negative emission", {{"m.gltf", R"GLTF({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0,1]}],"nodes":[{"mesh":0,"translation":[0,0,-1]},{"camera":0,"translation":[0,0,3]}],"cameras":[{"type":"perspective","perspective":{"yfov":0.8,"znear":0.01}}],"materials":[{"pbrMetallicRoughness":{"baseColorFactor":[0.8,0.2,0.2,1],"metallicFactor":0,"roughnessFactor":0.5},"emissiveFactor":[-1,0,0]}],"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,"material":0}]}],"buffers":[{"byteLength":44,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA="}],"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}]})GLTF"}},
               "render -q {d}/m.gltf -o {d}/o.exr", 1, {"m.gltf", "emissive"}});
  v.push_back({"glTF node scaled by 0", {{"m.gltf", R"GLTF({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0,1]}],"nodes":[{"mesh":0,"translation":[0,0,-1],"scale":[0,0,0]},{"camera":0,"translation":[0,0,3]}],"cameras":[{"type":"perspective","perspective":{"yfov":0.8,"znear":0.01}}],"materials":[{"pbrMetallicRoughness":{"baseColorFactor":[0.8,0.2,0.2,1],"metallicFactor":0,"roughnessFactor":0.5},"emissiveFactor":[1,1,1]}],"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,"material":0}]}],"buffers":[{"byteLength":44,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA="}],"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}]})GLTF"}},
               "render -q {d}/m.gltf -o {d}/o.exr", 1, {"m.gltf", "singular"}});
  v.push_back({"PLY with a NaN vertex", {{"m.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                               "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                               "end_header\nnan 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"}},
               "render -q {d}/m.ply -o {d}/o.exr", 1, {"m.ply"}});
  v.push_back({"PLY garbage", {{"m.ply", "ply\nformat ascii 1.0\nelement vertex x\n"}}, "render -q {d}/m.ply -o {d}/o.exr", 1,
               {"m.ply"}});
  v.push_back({"PLY without faces", {{"m.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                               "property float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n"}},
               "render -q {d}/m.ply -o {d}/o.exr", 1, {"m.ply"}});
  v.push_back({"plymesh that is empty", {{"s.pbrt", world_line("Shape \"plymesh\" \"string filename\" \"m.ply\"")}, {"m.ply", ""}},
               kRender, 1, {"m.ply"}});
  v.push_back({"objmesh of random bytes", {{"s.pbrt", world_line("Shape \"objmesh\" \"string filename\" \"m.obj\"")},
                                           {"m.obj", "\x01\x02 nothing\n"}},
               kRender, 1, {"s.pbrt:8", "no triangles"}});
  v.push_back({"gltfmesh without meshes", {{"s.pbrt", world_line("Shape \"gltfmesh\" \"string filename\" \"m.gltf\"")},
                                           {"m.gltf", R"({"asset": {"version": "2.0"}})"}},
               kRender, 1, {"s.pbrt:8", "no triangles"}});
  v.push_back({"imagemap that is not an image", {{"s.pbrt", world_line("Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" "
                                                                     "\"t.png\"")}, {"t.png", "not a png"}},
               kRender, 1, {"s.pbrt:8", "t.png"}});
  v.push_back({"directory as the scene", {{"dir.pbrt/", ""}}, "render -q {d}/dir.pbrt -o {d}/o.exr", 1, {"dir.pbrt", "directory"}});
  v.push_back({"directory as an OBJ scene", {{"dir.obj/", ""}}, "render -q {d}/dir.obj -o {d}/o.exr", 1, {"dir.obj", "directory"}});
  v.push_back({"missing scene", {}, "render -q {d}/none.pbrt -o {d}/o.exr", 1, {"none.pbrt"}});
  v.push_back({"unknown directive", {{"s.pbrt", world_line("Frobnicate 1")}}, kRender, 1, {"s.pbrt:8", "Frobnicate"}});
  v.push_back({"unterminated string", {{"s.pbrt", world_line("Shape \"sphere")}}, kRender, 1, {"s.pbrt:8", "unterminated"}});
  v.push_back({"truncated parameter list", {{"s.pbrt", world_line("Shape \"sphere\" \"float radius\" [1")}}, kRender, 1,
               {"s.pbrt:8", "radius"}});
  v.push_back({"scene with no WorldBegin", {{"s.pbrt", "Camera \"perspective\"\n"}}, kRender, 1, {"s.pbrt", "WorldBegin"}});

  // Outputs: never onto an input or another output, the right extension, folders that can exist.
  const std::string r = "render -q --spp 1 {d}/s.pbrt ";
  const std::vector<std::pair<std::string, std::string>> scene = {{"s.pbrt", good_scene()}};
  auto out = [&](const std::string& name, const std::string& args, std::vector<std::string> expect,
                 std::vector<std::pair<std::string, std::string>> files = {}) {
    files.insert(files.begin(), scene.begin(), scene.end());
    v.push_back({name, files, r + args, 1, std::move(expect)});
  };
  out("-o onto the scene", "-o {d}/s.pbrt", {"-o", "s.pbrt", "input"});
  out("--png onto the scene", "--png {d}/s.pbrt", {"--png", "s.pbrt", "input"});
  out("--average onto the scene", "--average {d}/s.pbrt", {"--average", "s.pbrt"});
  out("--timings onto the scene", "--timings {d}/s.pbrt -o {d}/o.exr", {"--timings", "s.pbrt"});
  out("-o onto the config", "--config {d}/c.json -o {d}/c.json", {"-o", "c.json"}, {{"c.json", "{}"}});
  out("sidecar onto the config", "--config {d}/o.json -o {d}/o.exr", {"o.json", "input"}, {{"o.json", "{}"}});
  out("sidecar onto a user's JSON file", "-o {d}/o.exr", {"o.json", "not a restir sidecar"}, {{"o.json", "{\"mine\": 1}"}});
  out("sidecar onto a non-JSON file", "--png {d}/o.png", {"o.json"}, {{"o.json", "precious notes"}});
  out("-o onto an included file", "-o {d}/inc.exr", {"-o", "inc.exr", "input"}, {{"s.pbrt", world_line("Include \"inc.exr\"")},
                                                                                 {"inc.exr", "\n"}});
  out("--png onto a texture", "--png {d}/t.png", {"--png", "t.png", "input"});
  v.back().files = {{"s.pbrt", world_line("Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"t.png\"")}};
  v.back().files.push_back({"t.png", tiny_png()});
  out("-o and --png the same file", "-o {d}/a.exr --png {d}/a.exr", {"--png", "a.exr"});
  out("-o and --average the same file", "-o {d}/a.exr --average {d}/a.exr", {"--average", "-o"});
  out("-o with a PNG extension", "-o {d}/x.png", {"-o", "x.png", ".exr"});
  out("-o with no extension", "-o {d}/x", {"-o", ".exr"});
  out("--png with an EXR extension", "--png {d}/x.exr", {"--png", ".png"});
  out("--average with a PNG extension", "--average {d}/x.png", {"--average", ".exr"});
  out("--timings with an EXR extension", "-o {d}/o.exr --timings {d}/t.exr", {"--timings", ".csv"});
  out("-o onto a directory", "-o {d}/dir.exr", {"-o", "directory"}, {{"dir.exr/", ""}});
  out("--frame-dir onto a file", "--frame-dir {d}/f.txt", {"--frame-dir", "not a directory"}, {{"f.txt", "x"}});
  out("--frame-dir over -o", "--frame-dir {d}/fr -o {d}/fr/frame_0000.exr", {"--frame-dir", "frame_0000.exr"});
  out("--frame-dir over the config", "--config {d}/frame_0000.exr --frame-dir {d} -o {d}/o.exr",
      {"--frame-dir", "frame_0000.exr"}, {{"frame_0000.exr", "{}"}});
  out("-o under a file used as a folder", "-o {d}/f.txt/o.exr", {"-o", "f.txt"}, {{"f.txt", "x"}});

  // Usage errors: exit status 2, one line, readable ranges.
  auto usage = [&](const std::string& name, const std::string& args, std::vector<std::string> expect) {
    v.push_back({name, scene, args, 2, std::move(expect)});
  };
  usage("bare restir", "", {"command is required"});
  usage("unknown command", "frobnicate", {"frobnicate"});
  usage("render without a scene", "render -o {d}/o.exr", {"scene"});
  usage("render without an output", "render {d}/s.pbrt", {"no output"});
  usage("--spp 0", "render {d}/s.pbrt -o {d}/o.exr --spp 0", {"--spp", "[1, 2147483647]"});
  usage("--spp=-3", "render {d}/s.pbrt -o {d}/o.exr --spp=-3", {"--spp"});
  usage("--spp abc", "render {d}/s.pbrt -o {d}/o.exr --spp abc", {"--spp", "abc"});
  usage("--spp overflow", "render {d}/s.pbrt -o {d}/o.exr --spp 99999999999", {"--spp"});
  usage("--frames 0", "render {d}/s.pbrt -o {d}/o.exr --frames 0", {"--frames", "[1, 2147483647]"});
  usage("--threads=-1", "render {d}/s.pbrt -o {d}/o.exr --threads=-1", {"--threads", "[0, "});
  usage("--seed=-5", "render {d}/s.pbrt -o {d}/o.exr --seed=-5", {"--seed"});
  usage("unknown flag", "render {d}/s.pbrt -o {d}/o.exr --frobnicate", {"--frobnicate"});
  usage("study --jobs 0", "study x --out {d}/st --jobs 0", {"--jobs"});
  usage("study without --out", "study quick", {"--out"});
  usage("study without a name", "study --out {d}/st", {"study"});

  // Options and configs: bad values are errors naming the key (exit 1).
  auto opt = [&](const std::string& name, const std::string& args, std::vector<std::string> expect,
                 std::vector<std::pair<std::string, std::string>> files = {}) {
    files.insert(files.begin(), scene.begin(), scene.end());
    v.push_back({name, files, std::string(kRender) + " " + args, 1, std::move(expect)});
  };
  opt("config with an overflowing number", "--config {d}/c.json", {"c.json", "1e400"}, {{"c.json", R"({"render": {"spp": 1e400}})"}});
  opt("config that is not JSON", "--config {d}/c.json", {"c.json", "invalid JSON"}, {{"c.json", "{spp: 1"}});
  opt("config with an unknown key", "--config {d}/c.json", {"c.json", "render.nope"}, {{"c.json", R"({"render": {"nope": 1}})"}});
  opt("config with a huge float", "--config {d}/c.json", {"c.json", "film.filter_radius"},
      {{"c.json", R"({"film": {"filter_radius": 1e300}})"}});
  opt("config that is a directory", "--config {d}/cdir", {"cdir"}, {{"cdir/", ""}});
  opt("both DI candidate counts 0", "--integrator restir-di --set di.light_candidates=0 --set di.bsdf_candidates=0",
      {"di.light_candidates", "di.bsdf_candidates"});
  opt("--set a NaN", "--set film.filter_radius=nan", {"film.filter_radius"});
  opt("--set out of range", "--set film.width=2000000000", {"film.width", "2000000000", "[1, 16384]"});
  opt("--res 0x8", "--res 0x8", {"film.width"});
  opt("camera path eye at 1e300", "--set render.camera_path={d}/cp.json", {"cp.json", "eye"},
      {{"cp.json", R"({"keys": [{"eye": [1e300, 0, 0], "target": [0, 0, 1]}]})"}});
  opt("camera path with an overflowing number", "--set render.camera_path={d}/cp.json", {"cp.json"},
      {{"cp.json", R"({"keys": [{"eye": [1e400, 0, 0], "target": [0, 0, 1]}]})"}});
  opt("camera path fov 1e300", "--set render.camera_path={d}/cp.json", {"cp.json", "fov"},
      {{"cp.json", R"({"keys": [{"eye": [0, 0, 0], "target": [0, 0, 1], "fov": 1e300}]})"}});

  opt("camera path mirror not a bool", "--set render.camera_path={d}/cp.json", {"cp.json", "mirror"},
      {{"cp.json", R"({"keys": [{"eye": [0, 0, 0], "target": [0, 0, 1], "mirror": 1}]})"}});

#ifdef RESTIR_HAVE_VIEWER
  // The viewer refuses bad input before it opens a window (no display needed).
  v.push_back({"view: unknown script command", {scene[0], {"sc.txt", "frames 1\nzoom 2\n"}},
               "view {d}/s.pbrt --script {d}/sc.txt", 1, {"sc.txt:2", "zoom"}});
  v.push_back({"view: script frames 0", {scene[0], {"sc.txt", "# c\nframes 0\n"}}, "view {d}/s.pbrt --script {d}/sc.txt",
               1, {"sc.txt:2", "frames"}});
  v.push_back({"view: missing script", scene, "view {d}/s.pbrt --script {d}/none.txt", 1, {"--script", "none.txt"}});
  v.push_back({"view: --set out of range", scene, "view {d}/s.pbrt --set di.spatial_neighbors=99", 1,
               {"di.spatial_neighbors", "99"}});
  v.push_back({"view: missing reference", scene, "view {d}/s.pbrt --reference {d}/r.exr", 1, {"r.exr"}});
  v.push_back({"view: bad config", {scene[0], {"c.json", R"({"render": {"nope": 1}})"}}, "view {d}/s.pbrt --config {d}/c.json",
               1, {"c.json", "render.nope"}});
  usage("view --scale 0.3", "view {d}/s.pbrt --scale 0.3", {"--scale", "0.3"});
  usage("view without a scene", "view", {"scene"});
#endif

  // Studies: a plot that would be silently lost, a study that is not JSON.
  v.push_back({"study plot named -p", {{"s.pbrt", good_scene()}, {"st.json", R"({"scenes": ["s.pbrt"], "metrics": ["time"],
      "axes": [{"key": "render.spp", "values": [1, 2]}], "plots": [{"name": "-p", "x": "render.spp", "y": "time"}]})"}},
               "study {d}/st.json -q --out {d}/out", 1, {"st.json", "-p"}});
  v.push_back({"study file that is not JSON", {{"st.json", "{"}}, "study {d}/st.json -q --out {d}/out", 1, {"st.json"}});

  // compare: the metrics of a tone-mapped PNG against a linear EXR mean nothing.
  v.push_back({"compare PNG with EXR", {{"a.png", "x"}, {"b.exr", "x"}}, "compare {d}/a.png {d}/b.exr", 1, {"a.png", "b.exr"}});
  v.push_back({"compare a missing file", {}, "compare {d}/a.exr {d}/b.exr", 1, {"a.exr"}});
  return v;
}
