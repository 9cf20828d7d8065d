// pbrt-v4 scene files -> rl::Scene (a subset; pbrt-v4 is the reference for every meaning).
//
// Directives: Camera "perspective", Film, Sampler, Integrator, PixelFilter (-> SceneHints),
// LookAt, Transform, ConcatTransform, Translate, Rotate, Scale, Identity, CoordinateSystem,
// CoordSysTransform, ActiveTransform, TransformTimes, ReverseOrientation, AttributeBegin/End,
// TransformBegin/End (pbrt-v3), WorldBegin, WorldEnd (pbrt-v3, ignored), ObjectBegin/End/
// ObjectInstance (flattened), Include/Import, Shape (trianglemesh, plymesh, sphere, and the project
// extensions objmesh/gltfmesh), Material/MakeNamedMaterial/NamedMaterial (diffuse, conductor,
// dielectric, coateddiffuse), Texture (imagemap, checkerboard, constant, scale), AreaLightSource "diffuse",
// LightSource "infinite"/"point"/"spot"/"distant". ColorSpace, Option, Attribute: ignored with a warning.
// Media and everything else: SceneError "FILE:LINE: ...".
//
// Paths (plymesh, textures, env maps) are resolved as pbrt-v4 does, against the directory of the
// top-level scene file, falling back to the directory of the file that contains the directive;
// Include/Import try the including file's directory first, then the top-level one.
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <fmt/format.h>

#include "core/suggest.h"
#include "scene/pbrt_parser.h"

namespace rl {
namespace pbrt {

namespace fs = std::filesystem;
using Kind = Token::Kind;

Scene Parser::run() {
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
  for (const std::string& f : tok_.files()) scene_.input_files.push_back(f);
  return std::move(scene_);
}

float Parser::expect_number(const Token& d) {
  Token t = tok_.next();
  if (t.kind != Kind::word) d.fail(d.text + ": expected a number");
  float v = 0;
  try {
    size_t pos = 0;
    v = std::stof(t.text, &pos);
    if (pos != t.text.size()) throw std::invalid_argument(t.text);
  } catch (const std::out_of_range&) {
    t.fail(d.text + ": value '" + t.text + "' is not a finite number");
  } catch (const std::exception&) {
    t.fail(d.text + ": expected a number, got '" + t.text + "'");
  }
  if (!std::isfinite(v)) t.fail(d.text + ": value '" + t.text + "' is not a finite number");
  return v;
}

std::vector<float> Parser::expect_numbers(const Token& d, int n) {  // "[ n numbers ]" or n bare numbers
  bool br = tok_.peek().kind == Kind::lbracket;
  if (br) tok_.next();
  std::vector<float> v;
  for (int i = 0; i < n; ++i) v.push_back(expect_number(d));
  if (br && tok_.next().kind != Kind::rbracket) d.fail(d.text + ": expected ']' after " + std::to_string(n) + " numbers");
  return v;
}

std::string Parser::resolve(const std::string& f, const Token& d, bool include_first) const {
  fs::path p(f);
  if (p.is_absolute()) return f;
  fs::path here = fs::path(*d.file).parent_path() / p, top = main_dir_ / p;
  if (include_first) return fs::exists(here) || !fs::exists(top) ? here.string() : top.string();
  return fs::exists(top) || !fs::exists(here) ? top.string() : here.string();
}

// Every transform must stay finite and invertible: a singular or overflowing CTM would give
// non-finite geometry or rays later, far from the directive that caused it.
void Parser::apply(const Token& d, const Mat4& m, bool post) {
  for (int i = 0; i < 2; ++i) {
    if (!(active_ & (1 << i))) continue;
    Mat4 r = post ? gs_.ctm[i] * m : m, inv;
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        if (!std::isfinite(r.m[a][b])) d.fail(d.text + ": the current transform overflows (non-finite matrix)");
    if (!std::isfinite(r.det3())) d.fail(d.text + ": the current transform overflows (its determinant is not finite)");
    if (!r.inverse(inv) || r.det3() == 0) d.fail(d.text + ": the current transform becomes singular");
    gs_.ctm[i] = r;
  }
}

void Parser::directive(const Token& d) {
  const std::string& n = d.text;
  if (n == "Include" || n == "Import") {
    std::string f = resolve(expect_string(d), d, true);
    tok_.push_file(f, *d.file, d.line);
  } else if (transform_directive(d) || block_directive(d) || scene_directive(d)) {
    return;
  } else if (n == "MakeNamedMedium" || n == "MediumInterface") {
    d.fail("unsupported directive '" + n + "' (participating media are not supported)");
  } else {
    // pbrt-v4's directives that this parser reads: a misspelt one names the closest.
    static const std::vector<std::string> known = {"ActiveTransform", "AreaLightSource", "Attribute", "AttributeBegin", "AttributeEnd", "Camera", "ColorSpace", "ConcatTransform", "CoordSysTransform", "CoordinateSystem", "Film", "Identity", "Import", "Include", "Integrator", "LightSource", "LookAt", "MakeNamedMaterial", "Material", "NamedMaterial", "ObjectBegin", "ObjectEnd", "ObjectInstance", "Option", "PixelFilter", "ReverseOrientation", "Rotate", "Sampler", "Scale", "Shape", "Texture", "Transform", "TransformBegin", "TransformEnd", "TransformTimes", "Translate", "WorldBegin", "WorldEnd"};
    d.fail("unknown directive '" + n + "'" + did_you_mean(n, known));
  }
}

// The transform directives (pbrt-v4 "Transformations"); false if d is not one of them.
bool Parser::transform_directive(const Token& d) {
  const std::string& n = d.text;
  if (n == "Identity") {
    apply(d, Mat4::identity(), false);
  } else if (n == "Translate") {
    auto v = expect_numbers(d, 3);
    apply(d, translate(Vec3(v[0], v[1], v[2])));
  } else if (n == "Scale") {
    auto v = expect_numbers(d, 3);
    if (v[0] == 0 || v[1] == 0 || v[2] == 0) d.fail("Scale: a zero factor makes the transform singular");
    apply(d, scale(Vec3(v[0], v[1], v[2])));
  } else if (n == "Rotate") {
    auto v = expect_numbers(d, 4);
    if (v[1] == 0 && v[2] == 0 && v[3] == 0) d.fail("Rotate: zero axis");
    apply(d, rotate(v[0], Vec3(v[1], v[2], v[3])));
  } else if (n == "LookAt") {
    auto v = expect_numbers(d, 9);
    for (int i = 0; i < 6; ++i)
      if (std::fabs(v[size_t(i)]) > kMaxWorldCoordinate)
        d.fail(fmt::format("LookAt: {} {} lies beyond the supported world extent (|x| <= {:g})", i < 3 ? "eye" : "target",
                           v[size_t(i)], kMaxWorldCoordinate));
    Mat4 m;
    if (!look_at(Vec3(v[0], v[1], v[2]), Vec3(v[3], v[4], v[5]), Vec3(v[6], v[7], v[8]), m))
      d.fail("LookAt: degenerate (eye == target or up parallel to the view direction)");
    apply(d, m);
  } else if (n == "Transform" || n == "ConcatTransform") {
    auto v = expect_numbers(d, 16);
    Mat4 m;  // pbrt gives the matrix column by column: m[row][col] = v[col*4 + row]
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) m.m[r][c] = v[size_t(c * 4 + r)];
    Mat4 inv;
    if (!m.inverse(inv)) d.fail(n + ": singular matrix");
    apply(d, m, n == "ConcatTransform");
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
  } else {
    return false;
  }
  return true;
}

// AttributeBegin/End, TransformBegin/End, WorldBegin/End and ObjectBegin/End/ObjectInstance.
bool Parser::block_directive(const Token& d) {
  const std::string& n = d.text;
  if (n == "AttributeBegin" || n == "TransformBegin") {
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
  } else {
    return false;
  }
  return true;
}

// Camera, render settings, materials, textures, lights and shapes.
bool Parser::scene_directive(const Token& d) {
  const std::string& n = d.text;
  if (n == "Camera") {
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
    std::string target = expect_string(d);
    attribute(d, target, parse_params(tok_));
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
    pl.check_range("L", 0);
    pl.check_range("scale", 0);
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
  } else {
    return false;
  }
  return true;
}

void Parser::camera(const Token& d) {
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
  for (const Mat4* w : {&w0, &w1})
    if (!within_world(w->apply_point(Vec3(0))))
      d.fail("Camera: the camera position (from LookAt and the transforms before Camera) lies beyond the supported "
             "world extent");
  named_cs_["camera"] = {w0, w1};
}

void Parser::render_settings(const Token& d) {
  std::string type = expect_string(d);
  ParamList pl = parse_params(tok_);
  need_world(d, false);
  const std::string& n = d.text;
  SceneHints& h = scene_.hints;
  if (n == "Film") {  // pbrt-v4 defaults: 1280 x 720
    pl.check_range("xresolution", 1);
    pl.check_range("yresolution", 1);
    h.width = pl.get_int("xresolution", 1280);
    h.height = pl.get_int("yresolution", 720);
    note_hint(d, pl, "xresolution", "film.width");
    note_hint(d, pl, "yresolution", "film.height");
    if (pl.find("filename") && !warned_filename_) {
      warned_filename_ = true;
      warn(d, "Film \"filename\" ignored (the output path comes from the options)");
    }
  } else if (n == "Sampler") {
    // Sample positions come from render.sample_pattern; of pbrt's samplers only pixelsamples is read.
    // Unbiased either way: a pattern changes noise, not the mean.
    if (type != "independent" && type != "zsobol" && type != "sobol")
      warn(d, "Sampler \"" + type + "\": rendered with restir-lab's own sample positions (render.sample_pattern); only \"pixelsamples\" is read");
    pl.check_range("pixelsamples", 1);
    h.spp = pl.get_int("pixelsamples", 16);
    note_hint(d, pl, "pixelsamples", "render.spp");
  } else if (n == "Integrator") {
    // The integrator is an option (integrator=, --integrator); a path tracer's maxdepth carries over.
    if (type != "path" && type != "volpath" && type != "simplepath")
      warn(d, "Integrator \"" + type + "\" is not supported: rendered with the options' integrator (default pt, a unidirectional "
              "path tracer, as pbrt's \"path\"); only \"maxdepth\" is read");
    pl.check_range("maxdepth", 0);
    h.max_depth = pl.get_int("maxdepth", 5);
    note_hint(d, pl, "maxdepth", "path.max_depth");
  } else {
    float def = 0;
    if (type == "box") def = 0.5f;
    else if (type == "triangle") def = 2;
    else if (type == "gaussian") def = 1.5f;
    else d.fail("unsupported pixel filter '" + type + "' (box, triangle, gaussian)");
    h.pixel_filter = type;
    pl.check_range("xradius", 0, HUGE_VAL, true);
    pl.check_range("yradius", 0, HUGE_VAL, true);
    h.filter_radius = pl.get_float("xradius", def);
    note_hint(d, pl, "xradius", "film.filter_radius");
    if (pl.get_float("yradius", *h.filter_radius) != *h.filter_radius)
      warn(d, "PixelFilter: yradius != xradius; using xradius for both");
  }
  for (const std::string& u : pl.unused()) warn(d, n + ": parameter \"" + u + "\" ignored");
}

// Remembers where a render hint came from, so that a value the options refuse (xresolution
// 100000) is reported at its file:line with the parameter's name.
void Parser::note_hint(const Token& d, const ParamList& pl, const char* param, const char* option) {
  for (const pbrt::Param& p : pl.params)
    if (p.name == param)
      scene_.hints.where[option] = (p.file ? *p.file : "?") + ":" + std::to_string(p.line) + ": " + d.text +
                                   " parameter \"" + p.type + " " + p.name + "\"";
}

void Parser::texture(const Token& d, const std::string& name, const std::string& type, const std::string& cls,
                     const ParamList& pl) {
  if (type != "spectrum" && type != "float") d.fail("Texture: type must be \"spectrum\" or \"float\", got '" + type + "'");
  auto& names = type == "spectrum" ? tex_names_.spectrum : tex_names_.floats;
  if (names.count(name)) d.fail("texture '" + name + "' redefined");
  auto res = [&](const std::string& f) {
    std::string path = resolve(f, d, false);
    scene_.input_files.push_back(path);
    return path;
  };
  scene_.textures.push_back(pbrt::make_texture(d, name, cls, pl, tex_names_, scene_.textures, res));
  names[name] = int(scene_.textures.size()) - 1;
}

}  // namespace pbrt

Scene detail::parse_pbrt(const std::string& path) {
  pbrt::Parser p(path);
  return p.run();
}

}  // namespace rl
