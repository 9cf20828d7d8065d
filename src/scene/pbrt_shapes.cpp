// The pbrt-v4 parser's shapes, lights, attributes and object instances (see pbrt_parser.cpp).
#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "scene/pbrt_parser.h"
#include "scene/ply.h"

namespace rl::pbrt {

namespace fs = std::filesystem;

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

void Parser::light(const Token& d, const std::string& type, const ParamList& pl) {
  if (current_instance_) d.fail("LightSource inside ObjectBegin is not supported");
  pl.check_range("scale", 0);
  pl.check_range("L", 0);
  pl.check_range("I", 0);
  pl.check_range("power", 0);
  float sc = pl.get_float("scale", 1);
  if (type == "point") {
    PointLight l;
    l.intensity = pl.get_rgb("I", true).value_or(Rgb(1)) * sc;
    l.position = gs_.ctm[0].apply_point(pl.get_point3("from", Vec3(0)));
    if (!within_world(l.position)) d.fail("point light: \"from\" lies beyond the supported world extent after the transform");
    pl.check_unused("LightSource \"point\"");
    l.animation = gs_.light_animation;
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
      scene_.input_files.push_back(e.filename);
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
    e.animation = gs_.light_animation;
    scene_.environment = std::move(e);
  } else if (type == "spot") {
    spot_light(d, pl, sc);
  } else if (type == "distant") {
    distant_light(d, pl, sc);
  } else {
    d.fail("unsupported light '" + type + "' (supported: point, spot, distant, infinite, and AreaLightSource \"diffuse\")");
  }
}

// "from" and "to" of a spot or distant light under the CTM: both in world space, or a one-line
// error naming the parameter (pbrt-v4 would normalize a zero vector into NaNs).
std::pair<Vec3, Vec3> Parser::light_from_to(const Token& d, const ParamList& pl, const std::string& what) {
  auto fail = [&](const char* name, const std::string& msg) {  // at the parameter when it was given
    if (const Param* p = pl.find(name)) p->fail(msg);
    d.fail(msg);
  };
  const Vec3 from = gs_.ctm[0].apply_point(pl.get_point3("from", Vec3(0)));
  const Vec3 to = gs_.ctm[0].apply_point(pl.get_point3("to", Vec3(0, 0, 1)));
  const std::pair<const char*, Vec3> ends[] = {{"from", from}, {"to", to}};
  for (const auto& [name, p] : ends)
    if (!within_world(p)) fail(name, what + ": \"" + name + "\" lies beyond the supported world extent after the transform");
  if (!(length(to - from) > 0))
    fail(pl.find("to") ? "to" : "from", what + ": \"from\" and \"to\" coincide (after the transform): the light has no direction");
  return {from, to};
}

// pbrt-v4 SpotLight::Create: the cone's axis from "from" toward "to", full intensity within
// coneangle - conedeltaangle of it, smoothstep falloff in cos theta out to coneangle (degrees).
// pbrt-v4 checks no angles; a cone outside (0, 180] or a band wider than the cone (or negative) is
// refused here, as is a transform that is not a similarity (it would make the cone elliptical).
// "power" is not read, as for point lights.
void Parser::spot_light(const Token& d, const ParamList& pl, float scale) {
  pl.check_range("coneangle", 0, 180, true);
  pl.check_range("conedeltaangle", 0);
  SpotLight l;
  l.cone_angle = pl.get_float("coneangle", 30);
  l.cone_delta = pl.get_float("conedeltaangle", 5);
  if (l.cone_delta > l.cone_angle) {
    const std::string msg = fmt::format("conedeltaangle {} exceeds coneangle {}: the falloff band must lie within the cone",
                                        format_number(l.cone_delta), format_number(l.cone_angle));
    pl.find("conedeltaangle")->fail(msg);
  }
  float uniform = 0;
  if (!uniform_scale(gs_.ctm[0], uniform))
    d.fail("spot light: the transform must be a rotation, translation and uniform scale (a shear or non-uniform scale would "
           "distort the cone)");
  l.intensity = pl.get_rgb("I", true).value_or(Rgb(1)) * scale;
  const auto [from, to] = light_from_to(d, pl, "spot light");
  l.position = from;
  l.direction = normalize(to - from);
  pl.check_unused("LightSource \"spot\"");
  l.animation = gs_.light_animation;
  scene_.spot_lights.push_back(l);
}

// pbrt-v4 DistantLight::Create: radiance L arriving from direction from - to (the CTM applies to
// both points); "illuminance" E_v > 0 multiplies the scale, as pbrt-v4 does once the spectrum is
// normalized to 1 nit (so rgb L (1,1,1) with illuminance E gives an irradiance E at normal incidence).
void Parser::distant_light(const Token& d, const ParamList& pl, float scale) {
  pl.check_range("illuminance", 0, HUGE_VAL, true);
  DistantLight l;
  l.radiance = pl.get_rgb("L", true).value_or(Rgb(1)) * scale * pl.get_float("illuminance", 1);
  const auto [from, to] = light_from_to(d, pl, "distant light");
  l.direction = normalize(from - to);
  pl.check_unused("LightSource \"distant\"");
  l.animation = gs_.light_animation;
  scene_.distant_lights.push_back(l);
}

TriangleMesh Parser::triangle_mesh_shape(const Token& d, const ParamList& pl, const Mat4& xf) {
  std::vector<Vec3> P = pl.get_point3s("P");
  if (P.empty()) d.fail("trianglemesh: missing \"point3 P\"");
  std::vector<int> idx = pl.get_ints("indices");
  if (idx.empty()) {
    if (P.size() != 3) d.fail("trianglemesh: \"integer indices\" required unless there are exactly 3 vertices");
    idx = {0, 1, 2};
  }
  std::vector<uint32_t> ui;
  for (int i : idx) {
    if (i < 0 || size_t(i) >= P.size())
      pl.find("indices")->fail("vertex index " + std::to_string(i) + " is out of range [0, " +
                               std::to_string(P.size() - 1) + "]");
    ui.push_back(uint32_t(i));
  }
  auto N = pl.get_normals("N");
  auto uv = pl.get_point2s("uv");
  pl.ignore("faceIndices");
  pl.check_unused("Shape \"trianglemesh\"");
  return detail::make_world_mesh(P, N, uv, ui, xf, gs_.reverse);
}

TriangleMesh Parser::ply_mesh_shape(const Token& d, const ParamList& pl, const Mat4& xf) {
  std::string f = pl.get_string("filename", "");
  if (f.empty()) d.fail("plymesh: missing \"string filename\"");
  std::string path = resolve(f, d, false);
  if (!fs::exists(path)) d.fail("plymesh: cannot open PLY file '" + path + "'");
  pl.check_unused("Shape \"plymesh\"");
  scene_.input_files.push_back(path);
  PlyMesh pm = read_ply(path);
  return detail::make_world_mesh(pm.positions, pm.normals, pm.uvs, pm.indices, xf, gs_.reverse);
}

Sphere Parser::sphere_shape(const Token& d, const ParamList& pl, const Mat4& xf) {
  pl.check_range("radius", 0, HUGE_VAL, true);
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
  if (!within_world(sp.center) || !(sp.radius <= kMaxWorldCoordinate))
    d.fail(fmt::format("sphere: \"radius\" {} lies beyond the supported world extent (|x| <= {:g}) after the transform",
                       sp.radius, kMaxWorldCoordinate));
  sp.material = gs_.material;
  sp.emission = gs_.area;
  sp.animation = gs_.shape_animation;
  sp.flip_normal = gs_.reverse != (xf.det3() < 0);
  return sp;
}

// Project extension (pbrt-v4 has no such shapes): the file's triangles with the current
// material, transform, orientation and area light; the file's own materials are ignored.
void Parser::mesh_file_shape(const Token& d, const std::string& type, const ParamList& pl, const Mat4& xf,
                             std::vector<TriangleMesh>& out) {
  std::string f = pl.get_string("filename", "");
  if (f.empty()) d.fail(type + ": missing \"string filename\"");
  std::string path = resolve(f, d, false);
  if (!fs::exists(path)) d.fail(type + ": cannot open file '" + path + "'");
  pl.check_unused("Shape \"" + type + "\"");
  scene_.input_files.push_back(path);
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
}

void Parser::add_shape(const Token& d, const std::string& type, const ParamList& pl, std::vector<TriangleMesh>& out) {
  const Mat4& xf = gs_.ctm[0];  // motion blur of shapes is not supported: start transform
  if (type == "trianglemesh") {
    out.push_back(triangle_mesh_shape(d, pl, xf));
  } else if (type == "plymesh") {
    out.push_back(ply_mesh_shape(d, pl, xf));
  } else if (type == "sphere") {
    Sphere sp = sphere_shape(d, pl, xf);
    (current_instance_ ? current_instance_->spheres : scene_.spheres).push_back(sp);
  } else if (type == "disk") {
    out.push_back(disk_shape(d, pl, xf));
  } else if (type == "bilinearmesh") {
    out.push_back(bilinear_mesh_shape(d, pl, xf));
  } else if (type == "objmesh" || type == "gltfmesh") {
    mesh_file_shape(d, type, pl, xf, out);
  } else {
    d.fail("unsupported shape '" + type + "' (supported: trianglemesh, plymesh, sphere, disk, bilinearmesh, objmesh, gltfmesh)");
  }
}

void Parser::shape(const Token& d, const std::string& type, const ParamList& pl) {
  if (current_instance_ && gs_.area) d.fail("area lights are not supported with object instancing (as in pbrt-v4)");
  std::vector<TriangleMesh>& out = current_instance_ ? current_instance_->meshes : scene_.meshes;
  size_t first = out.size();
  std::string src = *d.file + ":" + std::to_string(d.line);
  try {
    add_shape(d, type, pl, out);
  } catch (const std::exception& e) {
    if (detail::located(e)) throw;
    d.fail(type + ": " + e.what());
  }
  if (type != "sphere" && out.size() == first) d.fail(type + ": the shape has no triangles");
  for (size_t i = first; i < out.size(); ++i) {
    if (out[i].indices.empty()) d.fail(type + ": the shape has no triangles");
    out[i].material = gs_.material;
    out[i].emission = gs_.area;
    out[i].animation = gs_.shape_animation;
    if (out[i].source.empty()) out[i].source = src;
  }
}

// pbrt-v4's parameter defaults are not supported, except the project's "string animation" for
// "shape" and "light" (scene/animation.h): what follows in this attribute block moves.
void Parser::attribute(const Token& d, const std::string& target, const ParamList& pl) {
  const std::string f = pl.get_string("animation", "");
  if (!f.empty()) {
    if (target != "shape" && target != "light") d.fail("Attribute \"" + target + "\": \"string animation\" applies to \"shape\" or \"light\"");
    need_world(d, true);
    const std::string path = resolve(f, d, false);
    auto it = animation_ids_.find(path);
    if (it == animation_ids_.end()) {
      if (!fs::exists(path)) d.fail("Attribute: cannot open animation file '" + path + "'");
      try {
        scene_.animations.push_back(load_animation(path));
      } catch (const SceneError& e) {
        d.fail(std::string("Attribute \"string animation\": ") + e.what());
      }
      scene_.input_files.push_back(path);
      it = animation_ids_.emplace(path, int(scene_.animations.size()) - 1).first;
    }
    (target == "shape" ? gs_.shape_animation : gs_.light_animation) = it->second;
  }
  for (const std::string& u : pl.unused()) warn(d, "Attribute: parameter \"" + u + "\" ignored (parameter defaults are not supported)");
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
    if (gs_.shape_animation >= 0) m.animation = gs_.shape_animation;  // the instance moves
    scene_.meshes.push_back(std::move(m));
  }
  for (Sphere sp : inst.spheres) {
    float s;
    if (!uniform_scale(xf, s)) d.fail("ObjectInstance: spheres need a rotation, translation and uniform scale");
    sp.center = xf.apply_point(sp.center);
    sp.radius *= s;
    if (xf.det3() < 0) sp.flip_normal = !sp.flip_normal;
    if (gs_.shape_animation >= 0) sp.animation = gs_.shape_animation;
    scene_.spheres.push_back(sp);
  }
}

}  // namespace rl::pbrt
