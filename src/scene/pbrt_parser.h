// The pbrt-v4 parser's state and directives (internal to src/scene: pbrt_parser.cpp holds the
// directives, pbrt_shapes.cpp the shapes, lights, attributes and object instances).
#pragma once
#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "scene/loader.h"
#include "scene/pbrt_tokenizer.h"

namespace rl::pbrt {

// The graphics state that AttributeBegin saves and AttributeEnd restores.
struct GState {
  Mat4 ctm[2];
  int material = 0;
  bool reverse = false;
  std::optional<AreaEmission> area;
  int shape_animation = -1, light_animation = -1;  // Attribute "shape"/"light" "string animation"
};

struct Pushed {
  char kind;  // 'a' attribute, 't' transform, 'o' object
  GState state;
  std::string file;
  int line;
};

struct Instance {
  std::vector<TriangleMesh> meshes;
  std::vector<Sphere> spheres;
};

inline bool within_world(Vec3 p) {
  return std::fabs(p.x) <= kMaxWorldCoordinate && std::fabs(p.y) <= kMaxWorldCoordinate &&
         std::fabs(p.z) <= kMaxWorldCoordinate;  // false for NaN
}

// True if the linear part of m is a rotation times a uniform scale s > 0 (no shear, no projection).
bool uniform_scale(const Mat4& m, float& s);

class Parser {
 public:
  explicit Parser(const std::string& path) : main_path_(path) {
    main_dir_ = std::filesystem::path(path).parent_path();
    scene_.source_path = path;
    Material def;
    def.name = "default";
    scene_.materials.push_back(def);
  }
  Scene run();

 private:
  using Kind = Token::Kind;
  void warn(const Token& t, const std::string& msg) { pbrt::warn(t, msg); }
  std::string expect_string(const Token& d) {
    Token t = tok_.next();
    if (t.kind != Kind::string) d.fail(d.text + ": expected a quoted string argument");
    return t.text;
  }
  float expect_number(const Token& d);
  std::vector<float> expect_numbers(const Token& d, int n);  // "[ n numbers ]" or n bare numbers
  std::string resolve(const std::string& f, const Token& d, bool include_first) const;
  void apply(const Token& d, const Mat4& m, bool post = true);
  void need_world(const Token& d, bool world) {
    if (world && !in_world_) d.fail(d.text + " is not allowed before WorldBegin");
    if (!world && in_world_) d.fail(d.text + " is not allowed after WorldBegin");
  }
  void directive(const Token& d);
  bool transform_directive(const Token& d);
  bool block_directive(const Token& d);
  bool scene_directive(const Token& d);
  void camera(const Token& d);
  void render_settings(const Token& d);
  void note_hint(const Token& d, const ParamList& pl, const char* param, const char* option);
  int add_material(const Token& d, const std::string& type, const std::string& name, const ParamList& pl) {
    scene_.materials.push_back(make_material(d, type, name, pl, tex_names_, scene_.textures));
    return int(scene_.materials.size()) - 1;
  }
  void texture(const Token& d, const std::string& name, const std::string& type, const std::string& cls, const ParamList& pl);
  // pbrt_shapes.cpp
  void light(const Token& d, const std::string& type, const ParamList& pl);
  void spot_light(const Token& d, const ParamList& pl, float scale);
  void distant_light(const Token& d, const ParamList& pl, float scale);
  std::pair<Vec3, Vec3> light_from_to(const Token& d, const ParamList& pl, const std::string& what);
  void shape(const Token& d, const std::string& type, const ParamList& pl);
  // shape()'s kinds, each under the start transform xf (shape() fills in what they share)
  void add_shape(const Token& d, const std::string& type, const ParamList& pl, std::vector<TriangleMesh>& out);
  TriangleMesh triangle_mesh_shape(const Token& d, const ParamList& pl, const Mat4& xf);
  TriangleMesh ply_mesh_shape(const Token& d, const ParamList& pl, const Mat4& xf);
  Sphere sphere_shape(const Token& d, const ParamList& pl, const Mat4& xf);
  TriangleMesh disk_shape(const Token& d, const ParamList& pl, const Mat4& xf);           // pbrt_quadrics.cpp
  TriangleMesh bilinear_mesh_shape(const Token& d, const ParamList& pl, const Mat4& xf);  // pbrt_quadrics.cpp
  void mesh_file_shape(const Token& d, const std::string& type, const ParamList& pl, const Mat4& xf,
                       std::vector<TriangleMesh>& out);
  void instantiate(const Token& d, const Instance& inst);
  void attribute(const Token& d, const std::string& target, const ParamList& pl);

  Tokenizer tok_;
  std::string main_path_;
  std::filesystem::path main_dir_;
  Scene scene_;
  GState gs_;
  std::map<std::string, int> animation_ids_;  // animation file -> index in scene_.animations
  int active_ = 3;
  std::vector<int> saved_active_;
  std::vector<Pushed> stack_;
  bool in_world_ = false, warned_filename_ = false;
  std::map<std::string, std::array<Mat4, 2>> named_cs_;
  std::map<std::string, int> named_mat_;
  NamedTextures tex_names_;
  std::map<std::string, Instance> instances_;
  Instance* current_instance_ = nullptr;
};

}  // namespace rl::pbrt
