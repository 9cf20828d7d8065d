// Scene -> Mitsuba 3 (see mitsuba_export.h for the mapping and why each choice was made).
#include "scene/mitsuba_export.h"

#include <fmt/format.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "core/io_error.h"
#include "image/image_io.h"
#include "scene/lights.h"
#include "scene/loader.h"
#include "scene/microfacet.h"

namespace rl {

namespace fs = std::filesystem;

namespace {

std::string num(float v) { return fmt::format("{:.9g}", v); }
std::string vec(Vec3 v) { return fmt::format("{:.9g}, {:.9g}, {:.9g}", v.x, v.y, v.z); }
std::string rgb(const char* name, Rgb c) { return fmt::format("<rgb name=\"{}\" value=\"{}\"/>", name, vec(c)); }
std::string flt(const char* name, float v) { return fmt::format("<float name=\"{}\" value=\"{}\"/>", name, num(v)); }

float luminance_pos(Rgb c) { return std::max(luminance(c), 0.0f); }

// Binary little-endian PLY with float x y z [nx ny nz] [u v] and uchar/uint face lists, the
// layout Mitsuba's PLY loader reads fastest.
void write_ply(const std::string& path, const std::vector<Vec3>& p, const std::vector<Vec3>& n,
               const std::vector<Vec2>& uv, const std::vector<uint32_t>& idx) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw IoError("export-mitsuba: cannot write '" + path + "'");
  std::string header = fmt::format("ply\nformat binary_little_endian 1.0\nelement vertex {}\n"
                                   "property float x\nproperty float y\nproperty float z\n", p.size());
  if (!n.empty()) header += "property float nx\nproperty float ny\nproperty float nz\n";
  if (!uv.empty()) header += "property float u\nproperty float v\n";
  header += fmt::format("element face {}\nproperty list uchar uint vertex_indices\nend_header\n", idx.size() / 3);
  out << header;
  auto put = [&](float f) { out.write(reinterpret_cast<const char*>(&f), 4); };  // x86/ARM: little endian
  for (size_t i = 0; i < p.size(); ++i) {
    put(p[i].x), put(p[i].y), put(p[i].z);
    if (!n.empty()) put(n[i].x), put(n[i].y), put(n[i].z);
    if (!uv.empty()) put(uv[i].x), put(uv[i].y);
  }
  for (size_t t = 0; t < idx.size(); t += 3) {
    const unsigned char three = 3;
    out.write(reinterpret_cast<const char*>(&three), 1);
    out.write(reinterpret_cast<const char*>(&idx[t]), 12);
  }
  if (!out) throw IoError("export-mitsuba: cannot write '" + path + "'");
}

// A mesh as it goes to one PLY file.
struct PlyData {
  std::vector<Vec3> p, n;
  std::vector<Vec2> uv;
  std::vector<uint32_t> idx;
};

class Exporter {
 public:
  Exporter(const Scene& scene, const MitsubaExportSettings& s, const std::string& dir)
      : scene_(scene), s_(s), dir_(dir) {
    Bounds3 b = scene.bounds();
    diag_ = b.empty() ? 1.0f : std::max(length(b.diagonal()), 1e-6f);
  }
  std::vector<std::string> run();

 private:
  void integrator_and_sensor();
  std::string texture(const char* name, const Material& m);
  void material(size_t i);
  void mesh(size_t i);
  void sphere(size_t i);
  void lights();
  void spot(const SpotLight& l);
  void environment();
  std::string area_emitter(const AreaEmission& e, float area) const;
  bool textured(const Material& m) const { return m.reflectance_texture >= 0; }
  void note(std::string s) { notes_.push_back(std::move(s)); }

  const Scene& scene_;
  const MitsubaExportSettings& s_;
  std::string dir_;
  float diag_ = 1;
  std::string xml_;
  std::vector<std::string> notes_;
};

std::vector<std::string> Exporter::run() {
  fs::create_directories(fs::path(dir_) / "meshes");
  xml_ = "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<!-- written by `restir export-mitsuba` from " +
         scene_.source_path + " -->\n<scene version=\"3.0.0\">\n";
  integrator_and_sensor();
  for (size_t i = 0; i < scene_.materials.size(); ++i) material(i);
  for (size_t i = 0; i < scene_.meshes.size(); ++i) mesh(i);
  for (size_t i = 0; i < scene_.spheres.size(); ++i) sphere(i);
  lights();
  xml_ += "</scene>\n";
  write_text_file_atomic((fs::path(dir_) / "scene.xml").string(), xml_);
  return notes_;
}

void Exporter::integrator_and_sensor() {
  // Mitsuba's max_depth counts the camera-to-surface segment too (2 = direct lighting).
  xml_ += fmt::format("  <integrator type=\"path\">\n    <integer name=\"max_depth\" value=\"{}\"/>\n"
                      "  </integrator>\n", s_.max_depth + 1);
  Mat4 w;
  if (!s_.camera.camera_from_world.inverse(w)) throw SceneError("export-mitsuba: singular camera transform");
  Vec3 x{w.m[0][0], w.m[1][0], w.m[2][0]}, y{w.m[0][1], w.m[1][1], w.m[2][1]}, z{w.m[0][2], w.m[1][2], w.m[2][2]};
  Vec3 p{w.m[0][3], w.m[1][3], w.m[2][3]};
  // Mitsuba refuses scale in the camera transform; restir-lab normalizes its ray directions, so an
  // orthonormalized frame with the same handedness is the same camera when the axes are orthogonal.
  if (std::fabs(dot(x, y)) > 1e-3f || std::fabs(dot(y, z)) > 1e-3f || std::fabs(dot(x, z)) > 1e-3f ||
      std::fabs(length(x) - length(y)) > 1e-3f * length(y))
    note("camera transform has shear or non-uniform scale: exported orthonormalized");
  const float handed = w.det3() < 0 ? -1.0f : 1.0f;
  z = normalize(z);
  y = normalize(y - z * dot(y, z));
  x = cross(y, z) * handed;  // restir-lab image right
  Vec3 mx = -x;              // Mitsuba: image right is -x in camera space
  std::string m = fmt::format("{} {} {} {} {} {} {} {} {} {} {} {} 0 0 0 1", num(mx.x), num(y.x), num(z.x), num(p.x),
                              num(mx.y), num(y.y), num(z.y), num(p.y), num(mx.z), num(y.z), num(z.z), num(p.z));
  std::string filter;
  if (s_.filter == "box") {
    filter = "<rfilter type=\"box\"/>";
    if (std::fabs(s_.filter_radius - 0.5f) > 1e-6f) note("box filter radius != 0.5: Mitsuba's box is one pixel wide");
  } else if (s_.filter == "triangle") {
    filter = fmt::format("<rfilter type=\"tent\">{}</rfilter>", flt("radius", s_.filter_radius));
  } else {
    // restir-lab: sigma = radius / 3 truncated at the radius; Mitsuba truncates at 4 sigma.
    filter = fmt::format("<rfilter type=\"gaussian\">{}</rfilter>", flt("stddev", s_.filter_radius / 3));
    note("gaussian filter: Mitsuba truncates at 4 sigma, restir-lab at 3 sigma");
  }
  xml_ += fmt::format(
      "  <sensor type=\"perspective\">\n    {}\n    <string name=\"fov_axis\" value=\"smaller\"/>\n"
      "    {}\n    {}\n    <transform name=\"to_world\"><matrix value=\"{}\"/></transform>\n"
      "    <sampler type=\"independent\"><integer name=\"sample_count\" value=\"{}\"/></sampler>\n"
      "    <film type=\"hdrfilm\">\n      <integer name=\"width\" value=\"{}\"/>\n"
      "      <integer name=\"height\" value=\"{}\"/>\n      <string name=\"pixel_format\" value=\"rgb\"/>\n"
      "      {}\n    </film>\n  </sensor>\n",
      flt("fov", s_.camera.fov_degrees), flt("near_clip", 1e-4f * diag_), flt("far_clip", 1e4f * diag_), m, s_.spp,
      s_.width, s_.height, filter);
}

// A reflectance texture: constant -> rgb; image -> EXR of restir-lab's decoded (linear, scaled)
// image; checkerboard -> Mitsuba's, whose cells are half a uv unit (hence the 0.5 scale).
std::string Exporter::texture(const char* name, const Material& m) {
  if (!textured(m)) return rgb(name, m.reflectance);
  const Texture& t = scene_.textures[size_t(m.reflectance_texture)];
  switch (t.kind) {
    case Texture::Kind::constant: return rgb(name, t.value);
    case Texture::Kind::checkerboard:
      return fmt::format("<texture type=\"checkerboard\" name=\"{}\">{}{}<transform name=\"to_uv\">"
                         "<scale x=\"{}\" y=\"{}\"/><translate x=\"{}\" y=\"{}\"/><scale value=\"0.5\"/>"
                         "</transform></texture>", name, rgb("color0", t.tex1), rgb("color1", t.tex2),
                         num(t.uscale), num(t.vscale), num(t.udelta), num(t.vdelta));
    case Texture::Kind::image: {
      fs::create_directories(fs::path(dir_) / "textures");
      std::string file = fmt::format("textures/tex_{}.exr", m.reflectance_texture);
      if (!fs::exists(fs::path(dir_) / file)) write_exr((fs::path(dir_) / file).string(), t.image);
      // restir-lab: v = 0 is the image's bottom row; Mitsuba: the top row. Both bilinear, repeat.
      return fmt::format("<texture type=\"bitmap\" name=\"{}\"><string name=\"filename\" value=\"{}\"/>"
                         "<boolean name=\"raw\" value=\"true\"/><string name=\"wrap_mode\" value=\"repeat\"/>"
                         "<transform name=\"to_uv\"><scale x=\"{}\" y=\"{}\"/><translate x=\"{}\" y=\"{}\"/>"
                         "</transform></texture>", name, file, num(t.uscale), num(-t.vscale), num(t.udelta),
                         num(1 - t.vdelta));
    }
  }
  return rgb(name, m.reflectance);
}

void Exporter::material(size_t i) {
  const Material& m = scene_.materials[i];
  const bool smooth = std::max(m.alpha_x, m.alpha_y) < kSmoothAlpha;
  // make_bsdf clamps a rough lobe's axes to >= 1e-4.
  const float ax = std::max(m.alpha_x, 1e-4f), ay = std::max(m.alpha_y, 1e-4f);
  auto alphas = [&] {
    if (ax == ay) return flt("alpha", ax);
    note(fmt::format("material {} '{}': anisotropic alpha; the tangent directions of the two renderers differ", i, m.name));
    return flt("alpha_u", ax) + flt("alpha_v", ay);
  };
  std::string inner;
  bool two_sided = true;
  switch (m.type) {
    case Material::Type::diffuse:
      inner = fmt::format("<bsdf type=\"diffuse\">{}</bsdf>", texture("reflectance", m));
      break;
    case Material::Type::conductor: {
      Rgb eta = m.eta, k = m.k;
      if (m.use_reflectance) {
        Rgb r = m.reflectance;
        if (textured(m)) {
          const Texture& t = scene_.textures[size_t(m.reflectance_texture)];
          r = t.kind == Texture::Kind::constant ? t.value : 0.5f * (t.tex1 + t.tex2);
          if (t.kind != Texture::Kind::constant)
            note(fmt::format("material {} '{}': textured conductor reflectance exported as a constant", i, m.name));
        }
        r = min(max(r, Rgb(0)), Rgb(0.9999f));
        eta = Rgb(1);
        k = {2 * std::sqrt(r.x / (1 - r.x)), 2 * std::sqrt(r.y / (1 - r.y)), 2 * std::sqrt(r.z / (1 - r.z))};
      }
      std::string body = rgb("eta", eta) + rgb("k", k);
      inner = smooth ? fmt::format("<bsdf type=\"conductor\">{}</bsdf>", body)
                     : fmt::format("<bsdf type=\"roughconductor\"><string name=\"distribution\" value=\"ggx\"/>{}{}</bsdf>",
                                   alphas(), body);
      break;
    }
    case Material::Type::dielectric: {
      two_sided = false;
      std::string iors = flt("int_ior", m.ior) + flt("ext_ior", 1.0f);
      if (std::fabs(m.ior - 1) <= 1e-4f) inner = "<bsdf type=\"null\"/>";
      else if (smooth) inner = fmt::format("<bsdf type=\"dielectric\">{}</bsdf>", iors);
      else inner = fmt::format("<bsdf type=\"roughdielectric\"><string name=\"distribution\" value=\"ggx\"/>{}{}</bsdf>",
                               alphas(), iors);
      break;
    }
    case Material::Type::coated_diffuse: {
      // plastic / roughplastic with nonlinear = true: the model of bsdf_coated.h. roughplastic is
      // isotropic only: an anisotropic coat goes out with the mean alpha sqrt(alpha_x alpha_y).
      std::string body = flt("int_ior", m.ior) + flt("ext_ior", 1.0f) + texture("diffuse_reflectance", m) +
                         "<boolean name=\"nonlinear\" value=\"true\"/>";
      if (smooth) {
        inner = fmt::format("<bsdf type=\"plastic\">{}</bsdf>", body);
        break;
      }
      if (ax != ay) note(fmt::format("material {} '{}': anisotropic coat exported with alpha sqrt(alpha_u alpha_v) "
                                     "(Mitsuba's roughplastic is isotropic)", i, m.name));
      inner = fmt::format("<bsdf type=\"roughplastic\"><string name=\"distribution\" value=\"ggx\"/>{}{}</bsdf>",
                          flt("alpha", std::sqrt(ax * ay)), body);
      break;
    }
  }
  if (two_sided) xml_ += fmt::format("  <bsdf type=\"twosided\" id=\"mat{}\">{}</bsdf>\n", i, inner);
  else xml_ += fmt::format("  {}\n", inner.insert(inner.find(' '), fmt::format(" id=\"mat{}\"", i)));
}

// Emitter selection weight: restir-lab's own power heuristic (only the noise depends on it).
std::string Exporter::area_emitter(const AreaEmission& e, float area) const {
  float power = luminance_pos(e.radiance) * area * kPi;
  return fmt::format("<emitter type=\"area\">{}{}</emitter>", rgb("radiance", e.radiance),
                     flt("sampling_weight", std::isfinite(power) && power > 0 ? power : 1e-6f));
}

void Exporter::mesh(size_t i) {
  const TriangleMesh& m = scene_.meshes[i];
  const bool has_n = !m.normals.empty();
  const Material& mat = scene_.materials[size_t(m.material)];
  // Textured material without uvs: restir-lab uses the barycentrics (b1, b2) as uv.
  const bool bary_uv = m.uvs.empty() && textured(mat);
  const bool two_sided = m.emission && m.emission->two_sided;
  auto build = [&](int side) {  // side 0: as is; +1 / -1: the two-sided emitter's copies
    PlyData d;
    const bool unshared = side != 0 || bary_uv;
    float area = 0;
    for (uint32_t t = 0; t < m.triangle_count(); ++t) {
      uint32_t v[3] = {m.indices[3 * t], m.indices[3 * t + 1], m.indices[3 * t + 2]};
      const Vec3 ng = triangle_normal(m, t);
      area += 0.5f * length(cross(m.positions[v[1]] - m.positions[v[0]], m.positions[v[2]] - m.positions[v[0]]));
      // Wind so that cross(p1 - p0, p2 - p0) is restir-lab's normal (meshes without normals), or
      // the normal of this side (two-sided emitter copies).
      const Vec3 want = side < 0 ? -ng : ng;
      const bool swap = !(has_n && side == 0) && dot(cross(m.positions[v[1]] - m.positions[v[0]],
                                                           m.positions[v[2]] - m.positions[v[0]]), want) < 0;
      if (swap) std::swap(v[1], v[2]);
      if (!unshared) {
        d.idx.insert(d.idx.end(), v, v + 3);
        continue;
      }
      const Vec2 bary[3] = {{0, 0}, {1, 0}, {0, 1}};
      for (int k = 0; k < 3; ++k) {
        d.idx.push_back(uint32_t(d.p.size()));
        d.p.push_back(m.positions[v[k]] + ng * (float(side) * 1e-5f * diag_));
        if (has_n) d.n.push_back(side < 0 ? -m.normals[v[k]] : m.normals[v[k]]);
        if (!m.uvs.empty()) d.uv.push_back(m.uvs[v[k]]);
        else if (bary_uv) d.uv.push_back(bary[swap && k > 0 ? 3 - k : k]);
      }
    }
    if (!unshared) d.p = m.positions, d.n = m.normals, d.uv = m.uvs;
    std::string file = fmt::format("meshes/mesh_{}{}.ply", i, side < 0 ? "_back" : "");
    write_ply((fs::path(dir_) / file).string(), d.p, d.n, d.uv, d.idx);
    std::string emit = m.emission ? area_emitter(*m.emission, area) : "";
    xml_ += fmt::format("  <shape type=\"ply\"><string name=\"filename\" value=\"{}\"/>"
                        "<boolean name=\"face_normals\" value=\"{}\"/><ref id=\"mat{}\"/>{}</shape>\n",
                        file, has_n ? "false" : "true", m.material, emit);
  };
  if (m.triangle_count() == 0) return;
  if (two_sided) {
    build(+1);
    build(-1);
  } else {
    build(0);
  }
}

void Exporter::sphere(size_t i) {
  const Sphere& s = scene_.spheres[i];
  const bool two_sided = s.emission && s.emission->two_sided;
  const float r = std::fabs(s.radius), area = 4 * kPi * r * r;
  if (textured(scene_.materials[size_t(s.material)]))
    note(fmt::format("sphere {}: textured material, but the spheres' uv parameterizations differ", i));
  auto one = [&](float radius, bool flip, float emit_area) {
    std::string emit = s.emission ? area_emitter(*s.emission, emit_area) : "";
    xml_ += fmt::format("  <shape type=\"sphere\"><point name=\"center\" value=\"{}\"/>{}"
                        "<boolean name=\"flip_normals\" value=\"{}\"/><ref id=\"mat{}\"/>{}</shape>\n",
                        vec(s.center), flt("radius", radius), flip ? "true" : "false", s.material, emit);
  };
  if (!two_sided) {
    one(r, s.flip_normal, area);
  } else {  // outer copy faces out, inner copy faces in
    one(r + 1e-5f * diag_, false, area);
    one(std::max(r - 1e-5f * diag_, 0.5f * r), true, area);
  }
}

void Exporter::lights() {
  for (const PointLight& l : scene_.point_lights) {
    xml_ += fmt::format("  <emitter type=\"point\"><point name=\"position\" value=\"{}\"/>{}{}</emitter>\n",
                        vec(l.position), rgb("intensity", l.intensity),
                        flt("sampling_weight", std::max(4 * kPi * luminance_pos(l.intensity), 1e-6f)));
  }
  for (const SpotLight& l : scene_.spot_lights) spot(l);
  for (const DistantLight& l : scene_.distant_lights) {
    // Mitsuba's `direction` is the one the light travels: away from the light, -l.direction.
    const float r = 0.5f * diag_;  // the power heuristic of lights.cpp: pi r^2 L
    xml_ += fmt::format("  <emitter type=\"directional\"><vector name=\"direction\" value=\"{}\"/>{}{}</emitter>\n",
                        vec(-l.direction), rgb("irradiance", l.radiance),
                        flt("sampling_weight", std::max(kPi * r * r * luminance_pos(l.radiance), 1e-6f)));
  }
  if (scene_.environment) environment();
}

// Mitsuba's spot: the cone along +z of to_world (a look-at from the position along the axis),
// cutoff_angle = pbrt-v4's coneangle, beam_width = coneangle - conedeltaangle. Between the two
// Mitsuba's falloff is linear in the angle, pbrt-v4's a smoothstep in the cosine (see the header).
void Exporter::spot(const SpotLight& l) {
  const Frame f = Frame::from_normal(l.direction);  // f.s: an up vector perpendicular to the axis
  const float cos_start = l.cos_falloff_start(), cos_end = l.cos_falloff_end();
  const float power = 2 * kPi * luminance_pos(l.intensity) * ((1 - cos_start) + (cos_start - cos_end) / 2);
  // Mitsuba needs beam_width < cutoff_angle: a hard edge (conedeltaangle 0) keeps a tiny band.
  const float beam = std::min(l.cone_angle - l.cone_delta, l.cone_angle * (1 - 1e-6f));
  if (l.cone_delta > 0) note(fmt::format("spot light at ({}): falloff band {} deg, linear in angle in Mitsuba, smoothstep in "
                                         "cos theta in restir-lab (pbrt-v4); the full-intensity cone agrees",
                                         vec(l.position), num(l.cone_delta)));
  xml_ += fmt::format("  <emitter type=\"spot\"><transform name=\"to_world\"><lookat origin=\"{}\" target=\"{}\" up=\"{}\"/>"
                      "</transform>{}{}{}{}</emitter>\n",
                      vec(l.position), vec(l.position + l.direction), vec(f.s), rgb("intensity", l.intensity),
                      flt("cutoff_angle", l.cone_angle), flt("beam_width", beam), flt("sampling_weight", std::max(power, 1e-6f)));
}

// The environment as Mitsuba sees it: texels centred at Mitsuba's positions (theta = j / (H - 1)
// pi, align-corners rows; phi = (i + 0.5) / W 2 pi), world space, to_world = identity, evaluated
// with restir-lab's own lookup (orientation, mapping, scale and nearest-texel rule included).
void Exporter::environment() {
  const EnvironmentLight& env = *scene_.environment;
  if (env.mapping == EnvironmentLight::Mapping::constant || env.image.empty()) {
    xml_ += fmt::format("  <emitter type=\"constant\">{}</emitter>\n", rgb("radiance", env.radiance));
    return;
  }
  Scene only_env;
  only_env.environment = env;
  Lights lights(only_env, LightSelection::power);
  // Twice the source's rows (capped) so that the bilinear blur stays well below a source texel.
  const int h = std::min(2 * env.image.height, 2048), w = 2 * h;
  // Each Mitsuba texel gets restir-lab's radiance averaged over the texel's cell (4 x 4 strata,
  // weighted by sin(theta)), not a point sample: then the bilinearly reconstructed map keeps the
  // integral of restir-lab's piecewise-constant one (a point sample of a bright texel would
  // count it 2 or 3 times depending on how the grids line up).
  const int ss = 4;
  const float dtheta = kPi / float(h - 1);
  Image out(w, h);
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      Rgb sum(0);
      float wsum = 0;
      for (int a = 0; a < ss; ++a) {
        const float theta = clamp((float(j) - 0.5f + (float(a) + 0.5f) / ss) * dtheta, 0.0f, kPi);
        const float wt = std::max(std::sin(theta), 1e-6f);
        for (int b = 0; b < ss; ++b) {
          const float phi = (float(i) + (float(b) + 0.5f) / ss) / float(w) * 2 * kPi;
          const Vec3 d{std::sin(phi) * std::sin(theta), std::cos(theta), -std::cos(phi) * std::sin(theta)};
          sum += lights.environment_radiance(d) * wt;
          wsum += wt;
        }
      }
      out.at(i, j) = sum / wsum;
    }
  }
  write_exr((fs::path(dir_) / "envmap.exr").string(), out);
  xml_ += "  <emitter type=\"envmap\"><string name=\"filename\" value=\"envmap.exr\"/></emitter>\n";
  note(fmt::format("environment '{}' baked to envmap.exr ({}x{}, world space; Mitsuba filters it bilinearly, "
                   "restir-lab looks up the nearest texel: same integral, slightly softer edges)", env.filename, w, h));
}

}  // namespace

std::vector<std::string> export_mitsuba(const Scene& scene, const MitsubaExportSettings& settings,
                                        const std::string& dir) {
  return Exporter(scene, settings, dir).run();
}

}  // namespace rl
