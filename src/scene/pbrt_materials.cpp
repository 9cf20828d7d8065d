// pbrt-v4 materials and textures -> rl::Material / rl::Texture (internal to the pbrt loader).
#include <cmath>

#include "scene/coated.h"
#include "scene/loader.h"
#include "scene/pbrt_tokenizer.h"

namespace rl::pbrt {
namespace {

int reflectance_texture(const ParamList& pl, const std::string& name, const NamedTextures& nt) {
  const Param* p = pl.find(name);
  if (!p || p->type != "texture") return -1;
  auto t = pl.get_texture(name);
  auto it = nt.spectrum.find(*t);
  if (it == nt.spectrum.end()) {
    if (nt.floats.count(*t)) pl.find(name)->fail("texture '" + *t + "' is a float texture, a spectrum texture is needed");
    pl.find(name)->fail("unknown texture '" + *t + "'");
  }
  return it->second;
}

// A dielectric's (or coat's) "eta": a float, a single-value spectrum or one of pbrt-v4's named glasses.
float ior(const ParamList& pl, const std::string& type) {
  const Param* p = pl.find("eta");
  if (!p) return 1.5f;
  if (p->type == "float") return pl.get_float("eta", 1.5f);
  if (p->type == "spectrum" && p->strs.size() == 1) {
    auto ior = named_glass_ior(p->strs[0]);
    if (!ior) p->fail("unsupported named spectrum '" + p->strs[0] + "' (supported: glass-BK7, glass-BAF10, "
                      "glass-FK51A, glass-LASF9, glass-F5, glass-F10, glass-F11)");
    return *ior;
  }
  if (p->type == "spectrum" && p->nums.size() == 1) return float(p->nums[0]);
  p->fail(type + " eta must be a float, a single-value spectrum or a named glass");
}

// pbrt-v4 "coateddiffuse" as bsdf_coated.h's closed form: the base's reflectance (textured like
// diffuse's) and the coat's eta; the caller reads the roughness. The closed form has no layer
// thickness and needs no random walk, so "thickness", "maxdepth" and "nsamples" are read for their
// ranges only; a medium in the layer ("albedo" != 0, with its "g") is not modelled: one warning.
void coated_diffuse(const Token& d, const ParamList& pl, const NamedTextures& nt, Material& m) {
  m.type = Material::Type::coated_diffuse;
  m.reflectance_texture = reflectance_texture(pl, "reflectance", nt);
  if (m.reflectance_texture < 0) m.reflectance = pl.get_rgb("reflectance", false).value_or(Rgb(0.5f));
  m.ior = ior(pl, "coateddiffuse");
  if (!(m.ior > 0)) d.fail("coateddiffuse: eta must be positive");
  pl.check_range("thickness", 0, HUGE_VAL, true);
  pl.check_range("maxdepth", 1);
  pl.check_range("nsamples", 1);
  pl.check_range("g", -1, 1);
  pl.check_range("albedo", 0, 1);
  for (const char* k : {"thickness", "maxdepth", "nsamples", "g"}) pl.ignore(k);
  if (const Param* a = pl.find("albedo")) {
    const bool zero = a->type != "texture" && is_black(pl.get_rgb("albedo", false).value_or(Rgb(0)));
    pl.ignore("albedo");
    if (!zero) {
      Token at;
      at.file = a->file;
      at.line = a->line;
      warn(at, "coateddiffuse: \"albedo\" (a scattering medium in the coat) is not modelled: the layer is clear");
    }
  }
}

}  // namespace

Material make_material(const Token& d, const std::string& type, const std::string& name, const ParamList& pl,
                       const NamedTextures& nt, const std::vector<Texture>& textures) {
  Material m;
  m.name = name;
  auto roughness = [&] {
    // pbrt-v4: uroughness/vroughness default to "roughness" (default 0); remaproughness (default
    // true) maps through TrowbridgeReitzDistribution::RoughnessToAlpha(r) = sqrt(r).
    for (const char* k : {"roughness", "uroughness", "vroughness"}) pl.check_range(k, 0);
    float r = pl.get_float("roughness", 0);
    float u = pl.get_float("uroughness", r), v = pl.get_float("vroughness", r);
    if (u < 0 || v < 0) d.fail(type + ": negative roughness");
    bool remap = pl.get_bool("remaproughness", true);
    m.alpha_x = remap ? std::sqrt(u) : u;
    m.alpha_y = remap ? std::sqrt(v) : v;
  };
  // Physical ranges (a reflectance above 1 creates energy; eta <= 0 or k < 0 have no meaning).
  if (type == "diffuse" || type == "conductor" || type == "coateddiffuse") pl.check_range("reflectance", 0, 1);
  if (type == "conductor") {
    pl.check_range("eta", 0, HUGE_VAL, true);
    pl.check_range("k", 0);
  }
  if (type == "dielectric" || type == "coateddiffuse") pl.check_range("eta", 0, HUGE_VAL, true);
  if (type == "diffuse") {
    m.type = Material::Type::diffuse;
    m.reflectance_texture = reflectance_texture(pl, "reflectance", nt);
    if (m.reflectance_texture < 0) m.reflectance = pl.get_rgb("reflectance", false).value_or(Rgb(0.5f));
  } else if (type == "conductor") {
    m.type = Material::Type::conductor;
    const Param* refl = pl.find("reflectance");
    if (refl) {
      if (pl.find("eta") || pl.find("k")) d.fail("conductor: give either \"reflectance\" or \"eta\"/\"k\", not both");
      m.use_reflectance = true;
      m.reflectance_texture = reflectance_texture(pl, "reflectance", nt);
      if (m.reflectance_texture < 0) m.reflectance = *pl.get_rgb("reflectance", false);
    } else {
      m.eta = pl.get_rgb("eta", false).value_or(m.eta);  // default: pbrt-v4's metal-Cu-eta / metal-Cu-k
      m.k = pl.get_rgb("k", false).value_or(m.k);
    }
    roughness();
  } else if (type == "dielectric") {
    m.type = Material::Type::dielectric;
    m.ior = ior(pl, type);
    if (!(m.ior > 0)) d.fail("dielectric: eta must be positive");
    roughness();
  } else if (type == "coateddiffuse") {
    coated_diffuse(d, pl, nt, m);
    roughness();
    prepare_coated(m);
  } else if (type == "interface") {
    d.fail("unsupported material 'interface' (participating media are not supported)");
  } else {
    d.fail("unsupported material '" + type + "' (supported: diffuse, conductor, dielectric, coateddiffuse)");
  }
  pl.ignore("type");
  pl.check_unused("material \"" + type + "\"");
  (void)textures;
  return m;
}

namespace {
Rgb tex_value(const ParamList& pl, const std::string& name, Rgb def, const NamedTextures& nt,
              const std::vector<Texture>& textures) {
  const Param* p = pl.find(name);
  if (!p) return def;
  if (p->type == "float") return Rgb(pl.get_float(name, 0));
  if (p->type == "texture") {
    std::string t = *pl.get_texture(name);
    auto it = nt.spectrum.find(t);
    if (it == nt.spectrum.end()) it = nt.floats.find(t);
    if (it == nt.floats.end()) p->fail("unknown texture '" + t + "'");
    const Texture& tx = textures[size_t(it->second)];
    if (tx.kind != Texture::Kind::constant) p->fail("only constant textures can be nested here");
    return tx.value;
  }
  return *pl.get_rgb(name, false);
}

}  // namespace

Texture make_texture(const Token& d, const std::string& name, const std::string& cls, const ParamList& pl,
                     const NamedTextures& nt, const std::vector<Texture>& textures,
                     const std::function<std::string(const std::string&)>& resolve) {
  Texture t;
  t.name = name;
  for (const char* k : {"tex1", "tex2", "value", "tex"}) pl.check_range(k, 0);
  t.uscale = pl.get_float("uscale", 1);
  t.vscale = pl.get_float("vscale", 1);
  t.udelta = pl.get_float("udelta", 0);
  t.vdelta = pl.get_float("vdelta", 0);
  // A negative scale mirrors the texture (pbrt-v4 allows it; "vscale" -1 flips an image upright); a
  // zero one collapses it to one texel, which no scene means.
  for (const char* k : {"uscale", "vscale"})
    if (const Param* p = pl.find(k); p && pl.get_float(k, 1) == 0) p->fail("0 collapses the texture to one texel (a negative scale mirrors it)");
  std::string mapping = pl.get_string("mapping", "uv");
  if (mapping != "uv") d.fail("Texture: unsupported mapping '" + mapping + "' (only \"uv\")");
  if (cls == "imagemap") {
    std::string f = pl.get_string("filename", "");
    if (f.empty()) d.fail("imagemap: missing \"string filename\"");
    t.kind = Texture::Kind::image;
    t.image = detail::read_image_for(resolve(f), *d.file, d.line);
    pl.check_range("scale", 0);
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
    t.tex1 = tex_value(pl, "tex1", Rgb(1), nt, textures);
    t.tex2 = tex_value(pl, "tex2", Rgb(0), nt, textures);
  } else if (cls == "constant") {
    t.kind = Texture::Kind::constant;
    t.value = tex_value(pl, "value", Rgb(1), nt, textures);
  } else if (cls == "scale") {
    // scale = tex * scale; "tex" may name any texture (copied and multiplied), "scale" a constant.
    float s = 1;
    if (const Param* sp = pl.find("scale")) {
      if (sp->type != "float") sp->fail("only a constant float scale is supported");
      pl.check_range("scale", 0);  // a negative factor makes a negative reflectance (light from nowhere)
      s = pl.get_float("scale", 1);
    }
    const Param* tp = pl.find("tex");
    if (tp && tp->type == "texture") {
      std::string tn = *pl.get_texture("tex");
      auto it = nt.spectrum.find(tn);
      if (it == nt.spectrum.end()) it = nt.floats.find(tn);
      if (it == nt.floats.end()) tp->fail("unknown texture '" + tn + "'");
      std::string keep = name;
      t = textures[size_t(it->second)];
      t.name = keep;
    } else {
      t.kind = Texture::Kind::constant;
      t.value = tex_value(pl, "tex", Rgb(1), nt, textures);
    }
    t.value *= s;
    t.tex1 *= s;
    t.tex2 *= s;
    for (Rgb& c : t.image.pixels) c *= s;
  } else {
    d.fail("unsupported texture '" + cls + "' (supported: imagemap, checkerboard, constant, scale)");
  }
  pl.check_unused("Texture \"" + cls + "\"");
  return t;
}

}  // namespace rl::pbrt
