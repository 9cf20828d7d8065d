// pbrt-v4 scene files -> rl::Scene (a subset; pbrt-v4 is the reference for every meaning).
//
// Directives: Camera "perspective", Film, Sampler, Integrator, PixelFilter (-> SceneHints),
// LookAt, Transform, ConcatTransform, Translate, Rotate, Scale, Identity, CoordinateSystem,
// CoordSysTransform, ActiveTransform, TransformTimes, ReverseOrientation, AttributeBegin/End,
// TransformBegin/End (pbrt-v3), WorldBegin, WorldEnd (pbrt-v3, ignored), ObjectBegin/End/
// ObjectInstance (flattened), Include/Import, Shape (trianglemesh, plymesh, sphere, and the project
// extensions objmesh/gltfmesh), Material/MakeNamedMaterial/NamedMaterial (diffuse, conductor,
// dielectric), Texture (imagemap, checkerboard, constant, scale), AreaLightSource "diffuse",
// LightSource "infinite"/"point". ColorSpace, Option, Attribute: ignored with a warning.
// Media and everything else: SceneError "FILE:LINE: ...".
//
// Paths (plymesh, textures, env maps) are resolved as pbrt-v4 does, against the directory of the
// top-level scene file, falling back to the directory of the file that contains the directive;
// Include/Import try the including file's directory first, then the top-level one.
#include <array>
#include <cstdio>
#include <filesystem>
#include <map>

#include "scene/loader.h"
#include "scene/pbrt_tokenizer.h"
#include "scene/ply.h"

namespace rl {
namespace {

using pbrt::ParamList;
using pbrt::Token;
using Kind = pbrt::Token::Kind;
namespace fs = std::filesystem;

struct GState {
  Mat4 ctm[2];
  int material = 0;
  bool reverse = false;
  std::optional<AreaEmission> area;
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

class Parser {
 public:
  explicit Parser(const std::string& path) : main_path_(path) {
    main_dir_ = fs::path(path).parent_path();
    scene_.source_path = path;
    Material def;
    def.name = "default";
    scene_.materials.push_back(def);
  }

  Scene run() {
    tok_.push_file(main_path_, main_path_, 0);
    for (;;) {
      Token t = tok_.next();
      if (t.kind == Kind::eof) break;
      if (t.kind != Kind::word) t.fail("unexpected '" + t.text + "' (expected a directive)");
      directive(t);
    }
    if (!stack_.empty()) {
      const Pushed& p = stack_.back();
      const char* what = p.kind == 'a' ? "AttributeBegin" : p.kind == 't' ? "TransformBegin" : "ObjectBegin";
      throw SceneError(p.file, p.line, std::string(what) + " not closed before the end of the file");
    }
    if (!in_world_) throw SceneError(main_path_, 0, "no WorldBegin in the scene file");
    if (scene_.camera.keys.empty()) scene_.camera.keys.push_back(CameraKey{});  // pbrt default: fov 90 at the origin
    return std::move(scene_);
  }

 private:
  void warn(const Token& t, const std::string& msg) {
    std::fprintf(stderr, "%s:%d: warning: %s\n", t.file ? t.file->c_str() : "?", t.line, msg.c_str());
  }
  std::string expect_string(const Token& d) {
    Token t = tok_.next();
    if (t.kind != Kind::string) d.fail(d.text + ": expected a quoted string argument");
    return t.text;
  }
  float expect_number(const Token& d) {
    Token t = tok_.next();
    if (t.kind != Kind::word) d.fail(d.text + ": expected a number");
    try {
      size_t pos = 0;
      float v = std::stof(t.text, &pos);
      if (pos != t.text.size()) throw std::invalid_argument(t.text);
      return v;
    } catch (const std::exception&) {
      t.fail(d.text + ": expected a number, got '" + t.text + "'");
    }
  }
  std::vector<float> expect_numbers(const Token& d, int n) {  // "[ n numbers ]" or n bare numbers
    bool br = tok_.peek().kind == Kind::lbracket;
    if (br) tok_.next();
    std::vector<float> v;
    for (int i = 0; i < n; ++i) v.push_back(expect_number(d));
    if (br && tok_.next().kind != Kind::rbracket) d.fail(d.text + ": expected ']' after " + std::to_string(n) + " numbers");
    return v;
  }
  std::string resolve(const std::string& f, const Token& d, bool include_first) const {
    fs::path p(f);
    if (p.is_absolute()) return f;
    fs::path here = fs::path(*d.file).parent_path() / p, top = main_dir_ / p;
    if (include_first) return fs::exists(here) || !fs::exists(top) ? here.string() : top.string();
    return fs::exists(top) || !fs::exists(here) ? top.string() : here.string();
  }
  void apply(const Mat4& m, bool post = true) {
    for (int i = 0; i < 2; ++i)
      if (active_ & (1 << i)) gs_.ctm[i] = post ? gs_.ctm[i] * m : m;
  }
  void need_world(const Token& d, bool world) {
    if (world && !in_world_) d.fail(d.text + " is not allowed before WorldBegin");
    if (!world && in_world_) d.fail(d.text + " is not allowed after WorldBegin");
  }

  void directive(const Token& d) {
    const std::string& n = d.text;
    if (n == "Include" || n == "Import") {
      std::string f = resolve(expect_string(d), d, true);
      tok_.push_file(f, *d.file, d.line);
    } else if (n == "Identity") {
      apply(Mat4::identity(), false);
    } else if (n == "Translate") {
      auto v = expect_numbers(d, 3);
      apply(translate(Vec3(v[0], v[1], v[2])));
    } else if (n == "Scale") {
      auto v = expect_numbers(d, 3);
      apply(scale(Vec3(v[0], v[1], v[2])));
    } else if (n == "Rotate") {
      auto v = expect_numbers(d, 4);
      if (v[1] == 0 && v[2] == 0 && v[3] == 0) d.fail("Rotate: zero axis");
      apply(rotate(v[0], Vec3(v[1], v[2], v[3])));
    } else if (n == "LookAt") {
      auto v = expect_numbers(d, 9);
      Mat4 m;
      if (!look_at(Vec3(v[0], v[1], v[2]), Vec3(v[3], v[4], v[5]), Vec3(v[6], v[7], v[8]), m))
        d.fail("LookAt: degenerate (eye == target or up parallel to the view direction)");
      apply(m);
    } else if (n == "Transform" || n == "ConcatTransform") {
      auto v = expect_numbers(d, 16);
      Mat4 m;  // pbrt gives the matrix column by column: m[row][col] = v[col*4 + row]
      for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) m.m[r][c] = v[size_t(c * 4 + r)];
      Mat4 inv;
      if (!m.inverse(inv)) d.fail(n + ": singular matrix");
      apply(m, n == "ConcatTransform");
    } else if (n == "CoordinateSystem") {
      named_cs_[expect_string(d)] = {gs_.ctm[0], gs_.ctm[1]};
    } else if (n == "CoordSysTransform") {
      std::string name = expect_string(d);
      auto it = named_cs_.find(name);
      if (it == named_cs_.end()) d.fail("CoordSysTransform: unknown coordinate system '" + name + "'");
      for (int i = 0; i < 2; ++i)
        if (active_ & (1 << i)) gs_.ctm[i] = it->second[i];
    } else if (n == "ActiveTransform") {
      Token a = tok_.next();
      if (a.text == "StartTime") active_ = 1;
      else if (a.text == "EndTime") active_ = 2;
      else if (a.text == "All") active_ = 3;
      else a.fail("ActiveTransform: expected StartTime, EndTime or All, got '" + a.text + "'");
    } else if (n == "TransformTimes") {
      expect_numbers(d, 2);
    } else if (n == "ReverseOrientation") {
      gs_.reverse = !gs_.reverse;
    } else if (n == "AttributeBegin" || n == "TransformBegin") {
      stack_.push_back({n == "AttributeBegin" ? 'a' : 't', gs_, *d.file, d.line});
      saved_active_.push_back(active_);
    } else if (n == "AttributeEnd" || n == "TransformEnd") {
      char k = n == "AttributeEnd" ? 'a' : 't';
      if (stack_.empty() || stack_.back().kind != k) d.fail(n + " without a matching " + (k == 'a' ? "AttributeBegin" : "TransformBegin"));
      if (k == 'a') gs_ = stack_.back().state;
      else gs_.ctm[0] = stack_.back().state.ctm[0], gs_.ctm[1] = stack_.back().state.ctm[1];
      active_ = saved_active_.back();
      saved_active_.pop_back();
      stack_.pop_back();
    } else if (n == "WorldBegin") {
      need_world(d, false);
      in_world_ = true;
      gs_.ctm[0] = gs_.ctm[1] = Mat4::identity();
      active_ = 3;
      named_cs_["world"] = {Mat4::identity(), Mat4::identity()};
    } else if (n == "WorldEnd") {
      need_world(d, true);
    } else if (n == "Camera") {
      camera(d);
    } else if (n == "Film" || n == "Sampler" || n == "Integrator" || n == "PixelFilter") {
      render_settings(d);
    } else if (n == "ColorSpace") {
      expect_string(d);
      warn(d, "ColorSpace ignored (everything is linear sRGB)");
    } else if (n == "Option") {
      parse_params(tok_);
      warn(d, "Option ignored");
    } else if (n == "Attribute") {
      expect_string(d);
      parse_params(tok_);
      warn(d, "Attribute ignored (parameter defaults are not supported)");
    } else if (n == "MakeNamedMaterial") {
      std::string name = expect_string(d);
      ParamList pl = parse_params(tok_);
      need_world(d, true);
      if (named_mat_.count(name)) d.fail("named material '" + name + "' redefined");
      std::string type = pl.get_string("type", "");
      if (type.empty()) d.fail("MakeNamedMaterial '" + name + "': missing \"string type\"");
      named_mat_[name] = add_material(d, type, name, pl);
    } else if (n == "NamedMaterial") {
      std::string name = expect_string(d);
      auto it = named_mat_.find(name);
      if (it == named_mat_.end()) d.fail("NamedMaterial: unknown material '" + name + "'");
      gs_.material = it->second;
    } else if (n == "Material") {
      std::string type = expect_string(d);
      ParamList pl = parse_params(tok_);
      need_world(d, true);
      gs_.material = add_material(d, type, "", pl);
    } else if (n == "Texture") {
      std::string name = expect_string(d), type = expect_string(d), cls = expect_string(d);
      ParamList pl = parse_params(tok_);
      need_world(d, true);
      texture(d, name, type, cls, pl);
    } else if (n == "AreaLightSource") {
      std::string type = expect_string(d);
      ParamList pl = parse_params(tok_);
      need_world(d, true);
      if (type != "diffuse") d.fail("unsupported area light '" + type + "' (only \"diffuse\")");
      AreaEmission e;
      e.radiance = pl.get_rgb("L", true).value_or(Rgb(1)) * pl.get_float("scale", 1);
      e.two_sided = pl.get_bool("twosided", false);
      pl.check_unused("AreaLightSource \"diffuse\"");
      gs_.area = e;
    } else if (n == "LightSource") {
      std::string type = expect_string(d);
      ParamList pl = parse_params(tok_);
      need_world(d, true);
      light(d, type, pl);
    } else if (n == "Shape") {
      std::string type = expect_string(d);
      ParamList pl = parse_params(tok_);
      need_world(d, true);
      shape(d, type, pl);
    } else if (n == "ObjectBegin") {
      std::string name = expect_string(d);
      need_world(d, true);
      if (current_instance_) d.fail("ObjectBegin inside ObjectBegin");
      if (instances_.count(name)) d.fail("object '" + name + "' redefined");
      stack_.push_back({'o', gs_, *d.file, d.line});
      saved_active_.push_back(active_);
      current_instance_ = &instances_[name];
    } else if (n == "ObjectEnd") {
      if (stack_.empty() || stack_.back().kind != 'o') d.fail("ObjectEnd without a matching ObjectBegin");
      gs_ = stack_.back().state;
      active_ = saved_active_.back();
      saved_active_.pop_back();
      stack_.pop_back();
      current_instance_ = nullptr;
    } else if (n == "ObjectInstance") {
      std::string name = expect_string(d);
      need_world(d, true);
      if (current_instance_) d.fail("ObjectInstance inside ObjectBegin");
      auto it = instances_.find(name);
      if (it == instances_.end()) d.fail("ObjectInstance: unknown object '" + name + "'");
      instantiate(d, it->second);
    } else if (n == "MakeNamedMedium" || n == "MediumInterface") {
      d.fail("unsupported directive '" + n + "' (participating media are not supported)");
    } else {
      d.fail("unknown directive '" + n + "'");
    }
  }

  void camera(const Token& d) {
    std::string type = expect_string(d);
    ParamList pl = parse_params(tok_);
    need_world(d, false);
    if (type != "perspective") d.fail("unsupported camera '" + type + "' (only \"perspective\")");
    float fov = pl.get_float("fov", 90);
    if (!(fov > 0 && fov < 180)) d.fail("Camera: fov must be in (0, 180) degrees");
    if (pl.get_float("lensradius", 0) != 0) d.fail("Camera: lensradius > 0 (thin lens) is not supported");
    pl.ignore("focaldistance");
    pl.ignore("shutteropen");
    pl.ignore("shutterclose");
    pl.check_unused("Camera \"perspective\"");
    // pbrt-v4 interprets differing start/end camera transforms as motion blur within one frame;
    // this project reinterprets them as a camera animation across frames (keys[0] -> keys[1]).
    scene_.camera.keys = {CameraKey{gs_.ctm[0], fov}};
    bool differ = false;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) differ = differ || gs_.ctm[0].m[r][c] != gs_.ctm[1].m[r][c];
    if (differ) scene_.camera.keys.push_back(CameraKey{gs_.ctm[1], fov});
    Mat4 w0, w1;
    if (!gs_.ctm[0].inverse(w0) || !gs_.ctm[1].inverse(w1)) d.fail("Camera: singular camera transform");
    named_cs_["camera"] = {w0, w1};
  }

  void render_settings(const Token& d) {
    std::string type = expect_string(d);
    ParamList pl = parse_params(tok_);
    need_world(d, false);
    const std::string& n = d.text;
    SceneHints& h = scene_.hints;
    if (n == "Film") {  // pbrt-v4 defaults: 1280 x 720
      h.width = pl.get_int("xresolution", 1280);
      h.height = pl.get_int("yresolution", 720);
      if (*h.width <= 0 || *h.height <= 0) d.fail("Film: resolution must be positive");
      if (pl.find("filename") && !warned_filename_) {
        warned_filename_ = true;
        warn(d, "Film \"filename\" ignored (the output path comes from the options)");
      }
    } else if (n == "Sampler") {
      h.spp = pl.get_int("pixelsamples", 16);
      if (*h.spp <= 0) d.fail("Sampler: pixelsamples must be positive");
    } else if (n == "Integrator") {
      h.max_depth = pl.get_int("maxdepth", 5);
      if (*h.max_depth < 0) d.fail("Integrator: maxdepth must be >= 0");
    } else {
      float def = 0;
      if (type == "box") def = 0.5f;
      else if (type == "triangle") def = 2;
      else if (type == "gaussian") def = 1.5f;
      else d.fail("unsupported pixel filter '" + type + "' (box, triangle, gaussian)");
      h.pixel_filter = type;
      h.filter_radius = pl.get_float("xradius", def);
      if (pl.get_float("yradius", *h.filter_radius) != *h.filter_radius)
        warn(d, "PixelFilter: yradius != xradius; using xradius for both");
      if (!(*h.filter_radius > 0)) d.fail("PixelFilter: radius must be positive");
    }
    for (const std::string& u : pl.unused()) warn(d, n + ": parameter \"" + u + "\" ignored");
  }

  // Defined in the second half of this file.
  int add_material(const Token& d, const std::string& type, const std::string& name, const ParamList& pl);
  void texture(const Token& d, const std::string& name, const std::string& type, const std::string& cls,
               const ParamList& pl);
  void light(const Token& d, const std::string& type, const ParamList& pl);
  void shape(const Token& d, const std::string& type, const ParamList& pl);
  void instantiate(const Token& d, const Instance& inst);
  Rgb tex_value(const ParamList& pl, const std::string& name, Rgb def);
  int reflectance_texture(const Token& d, const ParamList& pl, const std::string& name);

  pbrt::Tokenizer tok_;
  std::string main_path_;
  fs::path main_dir_;
  Scene scene_;
  GState gs_;
  int active_ = 3;
  std::vector<int> saved_active_;
  std::vector<Pushed> stack_;
  bool in_world_ = false, warned_filename_ = false;
  std::map<std::string, std::array<Mat4, 2>> named_cs_;
  std::map<std::string, int> named_mat_, spectrum_tex_, float_tex_;
  std::map<std::string, Instance> instances_;
  Instance* current_instance_ = nullptr;
};

// True if the linear part of m is a rotation times a uniform scale s > 0 (no shear, no projection).
bool uniform_scale(const Mat4& m, float& s) {
  Vec3 c[3];
  for (int j = 0; j < 3; ++j) c[j] = Vec3(m.m[0][j], m.m[1][j], m.m[2][j]);
  float l0 = length(c[0]), l1 = length(c[1]), l2 = length(c[2]);
  s = l0;
  if (!(l0 > 0) || m.m[3][0] != 0 || m.m[3][1] != 0 || m.m[3][2] != 0 || m.m[3][3] != 1) return false;
  float tol = 1e-4f * l0;
  if (std::fabs(l1 - l0) > tol || std::fabs(l2 - l0) > tol) return false;
  float t2 = 1e-4f * l0 * l0;
  return std::fabs(dot(c[0], c[1])) <= t2 && std::fabs(dot(c[0], c[2])) <= t2 && std::fabs(dot(c[1], c[2])) <= t2;
}

int Parser::reflectance_texture(const Token& d, const ParamList& pl, const std::string& name) {
  const pbrt::Param* p = pl.find(name);
  if (!p || p->type != "texture") return -1;
  auto t = pl.get_texture(name);
  auto it = spectrum_tex_.find(*t);
  if (it == spectrum_tex_.end()) {
    if (float_tex_.count(*t)) pl.find(name)->fail("texture '" + *t + "' is a float texture, a spectrum texture is needed");
    pl.find(name)->fail("unknown texture '" + *t + "'");
  }
  return it->second;
}

int Parser::add_material(const Token& d, const std::string& type, const std::string& name, const ParamList& pl) {
  Material m;
  m.name = name;
  auto roughness = [&] {
    // pbrt-v4: uroughness/vroughness default to "roughness" (default 0); remaproughness (default
    // true) maps through TrowbridgeReitzDistribution::RoughnessToAlpha(r) = sqrt(r).
    float r = pl.get_float("roughness", 0);
    float u = pl.get_float("uroughness", r), v = pl.get_float("vroughness", r);
    if (u < 0 || v < 0) d.fail(type + ": negative roughness");
    bool remap = pl.get_bool("remaproughness", true);
    m.alpha_x = remap ? std::sqrt(u) : u;
    m.alpha_y = remap ? std::sqrt(v) : v;
  };
  if (type == "diffuse") {
    m.type = Material::Type::diffuse;
    m.reflectance_texture = reflectance_texture(d, pl, "reflectance");
    if (m.reflectance_texture < 0) m.reflectance = pl.get_rgb("reflectance", false).value_or(Rgb(0.5f));
  } else if (type == "conductor") {
    m.type = Material::Type::conductor;
    const pbrt::Param* refl = pl.find("reflectance");
    if (refl) {
      if (pl.find("eta") || pl.find("k")) d.fail("conductor: give either \"reflectance\" or \"eta\"/\"k\", not both");
      m.use_reflectance = true;
      m.reflectance_texture = reflectance_texture(d, pl, "reflectance");
      if (m.reflectance_texture < 0) m.reflectance = *pl.get_rgb("reflectance", false);
    } else {
      m.eta = pl.get_rgb("eta", false).value_or(m.eta);  // default: pbrt-v4's metal-Cu-eta / metal-Cu-k
      m.k = pl.get_rgb("k", false).value_or(m.k);
    }
    roughness();
  } else if (type == "dielectric") {
    m.type = Material::Type::dielectric;
    if (const pbrt::Param* p = pl.find("eta")) {
      if (p->type == "float") {
        m.ior = pl.get_float("eta", 1.5f);
      } else if (p->type == "spectrum" && p->strs.size() == 1) {
        auto ior = pbrt::named_glass_ior(p->strs[0]);
        if (!ior) p->fail("unsupported named spectrum '" + p->strs[0] + "' (supported: glass-BK7, glass-BAF10, "
                          "glass-FK51A, glass-LASF9, glass-F5, glass-F10, glass-F11)");
        m.ior = *ior;
      } else if (p->type == "spectrum" && p->nums.size() == 1) {
        m.ior = float(p->nums[0]);
      } else {
        p->fail("dielectric eta must be a float, a single-value spectrum or a named glass");
      }
    }
    if (!(m.ior > 0)) d.fail("dielectric: eta must be positive");
    roughness();
  } else if (type == "interface") {
    d.fail("unsupported material 'interface' (participating media are not supported)");
  } else {
    d.fail("unsupported material '" + type + "' (supported: diffuse, conductor, dielectric)");
  }
  pl.ignore("type");
  pl.check_unused("material \"" + type + "\"");
  scene_.materials.push_back(m);
  return int(scene_.materials.size()) - 1;
}

Rgb Parser::tex_value(const ParamList& pl, const std::string& name, Rgb def) {
  const pbrt::Param* p = pl.find(name);
  if (!p) return def;
  if (p->type == "float") return Rgb(pl.get_float(name, 0));
  if (p->type == "texture") {
    std::string t = *pl.get_texture(name);
    auto it = spectrum_tex_.find(t);
    if (it == spectrum_tex_.end()) it = float_tex_.find(t);
    if (it == float_tex_.end()) p->fail("unknown texture '" + t + "'");
    const Texture& tx = scene_.textures[size_t(it->second)];
    if (tx.kind != Texture::Kind::constant) p->fail("only constant textures can be nested here");
    return tx.value;
  }
  return *pl.get_rgb(name, false);
}

void Parser::texture(const Token& d, const std::string& name, const std::string& type, const std::string& cls,
                     const ParamList& pl) {
  if (type != "spectrum" && type != "float") d.fail("Texture: type must be \"spectrum\" or \"float\", got '" + type + "'");
  auto& names = type == "spectrum" ? spectrum_tex_ : float_tex_;
  if (names.count(name)) d.fail("texture '" + name + "' redefined");
  Texture t;
  t.name = name;
  t.uscale = pl.get_float("uscale", 1);
  t.vscale = pl.get_float("vscale", 1);
  t.udelta = pl.get_float("udelta", 0);
  t.vdelta = pl.get_float("vdelta", 0);
  std::string mapping = pl.get_string("mapping", "uv");
  if (mapping != "uv") d.fail("Texture: unsupported mapping '" + mapping + "' (only \"uv\")");
  if (cls == "imagemap") {
    std::string f = pl.get_string("filename", "");
    if (f.empty()) d.fail("imagemap: missing \"string filename\"");
    t.kind = Texture::Kind::image;
    t.image = detail::read_image_for(resolve(f, d, false), *d.file, d.line);
    float sc = pl.get_float("scale", 1);
    bool inv = pl.get_bool("invert", false);
    for (Rgb& c : t.image.pixels) c = inv ? Rgb(1) - c * sc : c * sc;
    std::string enc = pl.get_string("encoding", "sRGB");
    if (enc != "sRGB") warn(d, "imagemap: \"encoding\" '" + enc + "' ignored (8-bit images are decoded as sRGB)");
    std::string wrap = pl.get_string("wrap", "repeat");
    if (wrap != "repeat") warn(d, "imagemap: \"wrap\" '" + wrap + "' ignored (always repeat)");
    pl.ignore("filter");
    pl.ignore("maxanisotropy");
  } else if (cls == "checkerboard") {
    if (pl.get_int("dimension", 2) != 2) d.fail("checkerboard: only dimension 2 is supported");
    t.kind = Texture::Kind::checkerboard;
    t.tex1 = tex_value(pl, "tex1", Rgb(1));
    t.tex2 = tex_value(pl, "tex2", Rgb(0));
  } else if (cls == "constant") {
    t.kind = Texture::Kind::constant;
    t.value = tex_value(pl, "value", Rgb(1));
  } else if (cls == "scale") {
    // scale = tex * scale; "tex" may name any texture (copied and multiplied), "scale" a constant.
    float s = 1;
    if (const pbrt::Param* sp = pl.find("scale")) {
      if (sp->type != "float") sp->fail("only a constant float scale is supported");
      s = pl.get_float("scale", 1);
    }
    const pbrt::Param* tp = pl.find("tex");
    if (tp && tp->type == "texture") {
      std::string tn = *pl.get_texture("tex");
      auto it = spectrum_tex_.find(tn);
      if (it == spectrum_tex_.end()) it = float_tex_.find(tn);
      if (it == float_tex_.end()) tp->fail("unknown texture '" + tn + "'");
      std::string keep = name;
      t = scene_.textures[size_t(it->second)];
      t.name = keep;
    } else {
      t.kind = Texture::Kind::constant;
      t.value = tex_value(pl, "tex", Rgb(1));
    }
    t.value *= s;
    t.tex1 *= s;
    t.tex2 *= s;
    for (Rgb& c : t.image.pixels) c *= s;
  } else {
    d.fail("unsupported texture '" + cls + "' (supported: imagemap, checkerboard, constant, scale)");
  }
  pl.check_unused("Texture \"" + cls + "\"");
  scene_.textures.push_back(std::move(t));
  names[name] = int(scene_.textures.size()) - 1;
}

void Parser::light(const Token& d, const std::string& type, const ParamList& pl) {
  if (current_instance_) d.fail("LightSource inside ObjectBegin is not supported");
  float sc = pl.get_float("scale", 1);
  if (type == "point") {
    PointLight l;
    l.intensity = pl.get_rgb("I", true).value_or(Rgb(1)) * sc;
    l.position = gs_.ctm[0].apply_point(pl.get_point3("from", Vec3(0)));
    pl.check_unused("LightSource \"point\"");
    scene_.point_lights.push_back(l);
  } else if (type == "infinite") {
    if (scene_.environment) d.fail("only one infinite light is supported");
    EnvironmentLight e;
    auto L = pl.get_rgb("L", true);
    std::string f = pl.get_string("filename", "");
    if (L && !f.empty()) d.fail("infinite light: give either \"L\" or \"filename\", not both");
    e.world_from_light = gs_.ctm[0];
    if (!e.world_from_light.inverse(e.light_from_world)) d.fail("infinite light: singular transform");
    if (!f.empty()) {
      e.filename = resolve(f, d, false);
      e.image = detail::read_image_for(e.filename, *d.file, d.line);
      if (e.image.width == e.image.height) e.mapping = EnvironmentLight::Mapping::equal_area;
      else if (e.image.width == 2 * e.image.height) e.mapping = EnvironmentLight::Mapping::equirect;
      else d.fail("infinite light: image '" + f + "' is " + std::to_string(e.image.width) + "x" +
                  std::to_string(e.image.height) + "; expected square (equal-area) or 2:1 (equirectangular)");
      e.radiance = Rgb(sc);
    } else {
      e.mapping = EnvironmentLight::Mapping::constant;
      e.radiance = L.value_or(Rgb(1)) * sc;
    }
    pl.check_unused("LightSource \"infinite\"");
    scene_.environment = std::move(e);
  } else {
    d.fail("unsupported light '" + type + "' (supported: point, infinite, and AreaLightSource \"diffuse\")");
  }
}

void Parser::shape(const Token& d, const std::string& type, const ParamList& pl) {
  if (current_instance_ && gs_.area) d.fail("area lights are not supported with object instancing (as in pbrt-v4)");
  std::vector<TriangleMesh>& out = current_instance_ ? current_instance_->meshes : scene_.meshes;
  size_t first = out.size();
  std::string src = *d.file + ":" + std::to_string(d.line);
  const Mat4& xf = gs_.ctm[0];  // motion blur of shapes is not supported: start transform
  try {
    if (type == "trianglemesh") {
      std::vector<Vec3> P = pl.get_point3s("P");
      if (P.empty()) d.fail("trianglemesh: missing \"point3 P\"");
      std::vector<int> idx = pl.get_ints("indices");
      if (idx.empty()) {
        if (P.size() != 3) d.fail("trianglemesh: \"integer indices\" required unless there are exactly 3 vertices");
        idx = {0, 1, 2};
      }
      std::vector<uint32_t> ui;
      for (int i : idx) {
        if (i < 0) d.fail("trianglemesh: negative vertex index");
        ui.push_back(uint32_t(i));
      }
      auto N = pl.get_normals("N");
      auto uv = pl.get_point2s("uv");
      pl.ignore("faceIndices");
      pl.check_unused("Shape \"trianglemesh\"");
      out.push_back(detail::make_world_mesh(P, N, uv, ui, xf, gs_.reverse));
    } else if (type == "plymesh") {
      std::string f = pl.get_string("filename", "");
      if (f.empty()) d.fail("plymesh: missing \"string filename\"");
      std::string path = resolve(f, d, false);
      if (!fs::exists(path)) d.fail("plymesh: cannot open PLY file '" + path + "'");
      pl.check_unused("Shape \"plymesh\"");
      PlyMesh pm = read_ply(path);
      out.push_back(detail::make_world_mesh(pm.positions, pm.normals, pm.uvs, pm.indices, xf, gs_.reverse));
    } else if (type == "sphere") {
      float r = pl.get_float("radius", 1);
      float zmin = pl.get_float("zmin", -r), zmax = pl.get_float("zmax", r), phimax = pl.get_float("phimax", 360);
      if (zmin > -r || zmax < r || phimax < 360) d.fail("sphere: partial spheres (zmin/zmax/phimax) are not supported");
      pl.check_unused("Shape \"sphere\"");
      if (!(r > 0)) d.fail("sphere: radius must be positive");
      float s;
      if (!uniform_scale(xf, s)) d.fail("sphere: its transform must be a rotation, translation and uniform scale");
      Sphere sp;
      sp.center = xf.apply_point(Vec3(0));
      sp.radius = r * s;
      sp.material = gs_.material;
      sp.emission = gs_.area;
      sp.flip_normal = gs_.reverse != (xf.det3() < 0);
      (current_instance_ ? current_instance_->spheres : scene_.spheres).push_back(sp);
    } else if (type == "objmesh" || type == "gltfmesh") {
      // Project extension (pbrt-v4 has no such shapes): the file's triangles with the current
      // material, transform, orientation and area light; the file's own materials are ignored.
      std::string f = pl.get_string("filename", "");
      if (f.empty()) d.fail(type + ": missing \"string filename\"");
      std::string path = resolve(f, d, false);
      if (!fs::exists(path)) d.fail(type + ": cannot open file '" + path + "'");
      pl.check_unused("Shape \"" + type + "\"");
      detail::MeshImport opt;
      opt.world_from_object = xf;
      opt.reverse_orientation = gs_.reverse;
      opt.use_file_materials = false;
      opt.material = gs_.material;
      opt.emission = gs_.area;
      opt.error_file = *d.file;
      opt.error_line = d.line;
      if (type == "objmesh") detail::import_obj(path, opt, scene_, out);
      else detail::import_gltf(path, opt, scene_, out, nullptr);
    } else {
      d.fail("unsupported shape '" + type + "' (supported: trianglemesh, plymesh, sphere, objmesh, gltfmesh)");
    }
  } catch (const SceneError&) {
    throw;
  } catch (const std::exception& e) {
    d.fail(type + ": " + e.what());
  }
  for (size_t i = first; i < out.size(); ++i) {
    out[i].material = gs_.material;
    out[i].emission = gs_.area;
    if (out[i].source.empty()) out[i].source = src;
  }
}

void Parser::instantiate(const Token& d, const Instance& inst) {
  const Mat4& xf = gs_.ctm[0];
  for (TriangleMesh m : inst.meshes) {
    try {
      detail::transform_mesh(m, xf);
    } catch (const std::exception& e) {
      d.fail(std::string("ObjectInstance: ") + e.what());
    }
    m.source += " (instance at " + *d.file + ":" + std::to_string(d.line) + ")";
    scene_.meshes.push_back(std::move(m));
  }
  for (Sphere sp : inst.spheres) {
    float s;
    if (!uniform_scale(xf, s)) d.fail("ObjectInstance: spheres need a rotation, translation and uniform scale");
    sp.center = xf.apply_point(sp.center);
    sp.radius *= s;
    if (xf.det3() < 0) sp.flip_normal = !sp.flip_normal;
    scene_.spheres.push_back(sp);
  }
}

}  // namespace

Scene load_pbrt(const std::string& path) {
  Parser p(path);
  return p.run();
}

}  // namespace rl
