// OBJ+MTL (tinyobjloader) and glTF 2.0 (tinygltf) -> world-space triangle meshes.
//
// OBJ material mapping (MTL has no physically based model; this is the project's convention):
//   d < 1 or illum 4/6/7      -> dielectric, ior = Ni (1.5 if Ni <= 1)
//   Ks > 0, Ns >= 20 and lum(Ks) >= lum(Kd)
//                             -> conductor with reflectance = Ks, GGX alpha = sqrt(2 / (Ns + 2))
//                                (the Phong-exponent -> Beckmann/GGX-alpha correspondence of
//                                Walter et al. 2007, alpha^2 = 2 / (Ns + 2))
//   otherwise                 -> diffuse, reflectance = Kd (map_Kd -> image texture)
//   Ke > 0                    -> one-sided area emission Ke on the meshes using the material
// glTF: baseColorFactor/baseColorTexture -> diffuse reflectance; metallicFactor > 0.5 -> conductor
//   with reflectance = base colour and GGX alpha = roughnessFactor^2 (the glTF spec's alpha);
//   emissiveFactor (x KHR_materials_emissive_strength) -> emission, two-sided if doubleSided.
//   glTF texture coordinates have v = 0 at the image's top; they are stored as 1 - v (pbrt).
#include <tiny_gltf.h>
#include <tiny_obj_loader.h>
#include <nlohmann/json.hpp>
#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <map>
#include <tuple>

#include "scene/loader.h"

namespace rl::detail {
namespace {

namespace fs = std::filesystem;

std::string one_line(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}

float srgb_to_linear(float v) { return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f); }

// map_Kd as an image texture of the scene (read relative to the OBJ's folder); returns its index.
int obj_diffuse_texture(const std::string& texname, const std::string& dir, const std::string& path, Scene& scene) {
  Texture t;
  t.kind = Texture::Kind::image;
  t.name = texname;
  fs::path tp(texname);
  std::string full = tp.is_absolute() ? tp.string() : (fs::path(dir) / tp).string();
  scene.input_files.push_back(full);
  t.image = read_image_for(full, path, 0);
  scene.textures.push_back(std::move(t));
  return int(scene.textures.size()) - 1;
}

// An MTL material by the mapping at the top of this file (emission aside).
Material obj_material(const tinyobj::material_t& mt, const std::string& dir, const std::string& path, Scene& scene) {
  Material m;
  m.name = mt.name;
  Rgb kd(mt.diffuse[0], mt.diffuse[1], mt.diffuse[2]), ks(mt.specular[0], mt.specular[1], mt.specular[2]);
  if (mt.dissolve < 1 || mt.illum == 4 || mt.illum == 6 || mt.illum == 7) {
    m.type = Material::Type::dielectric;
    m.ior = mt.ior > 1 ? mt.ior : 1.5f;
  } else if (max_component(ks) > 0 && mt.shininess >= 20 && luminance(ks) >= luminance(kd)) {
    m.type = Material::Type::conductor;
    m.use_reflectance = true;
    m.reflectance = ks;
    m.alpha_x = m.alpha_y = std::sqrt(2.0f / (mt.shininess + 2.0f));
  } else {
    m.type = Material::Type::diffuse;
    m.reflectance = kd;
    if (!mt.diffuse_texname.empty()) m.reflectance_texture = obj_diffuse_texture(mt.diffuse_texname, dir, path, scene);
  }
  return m;
}

// The scene materials of an OBJ's MTL materials: per MTL material its scene material index and
// its emission (opt.material and none where the file's materials are not used).
struct ObjMaterials {
  std::vector<int> index;
  std::vector<std::optional<AreaEmission>> emission;
};

ObjMaterials import_obj_materials(const std::vector<tinyobj::material_t>& mats, const std::string& dir,
                                  const std::string& path, const MeshImport& opt, Scene& scene) {
  ObjMaterials r{std::vector<int>(mats.size(), opt.material), std::vector<std::optional<AreaEmission>>(mats.size())};
  if (!opt.use_file_materials) return r;
  for (size_t i = 0; i < mats.size(); ++i) {
    const tinyobj::material_t& mt = mats[i];
    Material m = obj_material(mt, dir, path, scene);
    Rgb ke(mt.emission[0], mt.emission[1], mt.emission[2]);
    if (max_component(ke) > 0) r.emission[i] = AreaEmission{ke, false};
    scene.materials.push_back(m);
    r.index[i] = int(scene.materials.size()) - 1;
  }
  return r;
}

// The triangles of one OBJ shape that use one material, with their own vertex list.
struct ObjGroup {
  std::vector<Vec3> p, n;
  std::vector<Vec2> uv;
  std::vector<uint32_t> idx;
  std::map<std::tuple<int, int, int>, uint32_t> remap;
  bool all_n = true, all_uv = true;
};

// Adds one triangle corner to g: a vertex already in g for the same (position, normal, uv)
// indices, or a new one.
void add_obj_corner(ObjGroup& g, const tinyobj::index_t& ix, const tinyobj::attrib_t& at, const std::string& path,
                    const std::string& shape) {
  auto key = std::make_tuple(ix.vertex_index, ix.normal_index, ix.texcoord_index);
  auto it = g.remap.find(key);
  if (it != g.remap.end()) {
    g.idx.push_back(it->second);
    return;
  }
  if (ix.vertex_index < 0 || (size_t(ix.vertex_index) * 3 + 2) >= at.vertices.size())
    throw SceneError(path, 0, "shape '" + shape + "': vertex index out of range");
  uint32_t id = uint32_t(g.p.size());
  g.remap[key] = id;
  g.idx.push_back(id);
  const float* v = &at.vertices[(size_t(ix.vertex_index) * 3)];
  g.p.emplace_back(v[0], v[1], v[2]);
  if (ix.normal_index >= 0 && (size_t(ix.normal_index) * 3 + 2) < at.normals.size()) {
    const float* n = &at.normals[(size_t(ix.normal_index) * 3)];
    g.n.emplace_back(n[0], n[1], n[2]);
  } else {
    g.all_n = false;
    g.n.emplace_back(0, 0, 0);
  }
  if (ix.texcoord_index >= 0 && (size_t(ix.texcoord_index) * 2 + 1) < at.texcoords.size()) {
    const float* t = &at.texcoords[(size_t(ix.texcoord_index) * 2)];
    g.uv.emplace_back(t[0], t[1]);
  } else {
    g.all_uv = false;
    g.uv.emplace_back(0, 0);
  }
}

// The shape's triangles grouped by material id (-1: none or out of range).
std::map<int, ObjGroup> group_obj_shape(const tinyobj::shape_t& sh, const tinyobj::attrib_t& at, size_t num_mats,
                                        const std::string& path) {
  std::map<int, ObjGroup> groups;
  size_t off = 0;
  const auto& fv = sh.mesh.num_face_vertices;
  for (size_t f = 0; f < fv.size(); ++f) {
    size_t nv = fv[f];
    int mid = f < sh.mesh.material_ids.size() ? sh.mesh.material_ids[f] : -1;
    if (mid >= int(num_mats)) mid = -1;
    ObjGroup& g = groups[mid];
    if (nv == 3)
      for (size_t k = 0; k < 3; ++k) add_obj_corner(g, sh.mesh.indices[off + k], at, path, sh.name);
    off += nv;
  }
  return groups;
}

// One world-space mesh per non-empty group of the shape.
void add_obj_meshes(std::map<int, ObjGroup>& groups, const tinyobj::shape_t& sh, const ObjMaterials& mats,
                    const std::string& path, const MeshImport& opt, std::vector<TriangleMesh>& out) {
  for (auto& [mid, g] : groups) {
    if (g.idx.empty()) continue;
    if (!g.all_n) g.n.clear();
    if (!g.all_uv) g.uv.clear();
    TriangleMesh m;
    try {
      m = make_world_mesh(g.p, g.n, g.uv, g.idx, opt.world_from_object, opt.reverse_orientation);
    } catch (const std::exception& e) {
      if (located(e)) throw;
      throw SceneError(path, 0, "shape '" + sh.name + "': " + e.what());
    }
    m.material = mid >= 0 ? mats.index[size_t(mid)] : opt.material;
    m.emission = opt.use_file_materials ? (mid >= 0 ? mats.emission[size_t(mid)] : std::nullopt) : opt.emission;
    m.source = path + ":" + sh.name;
    out.push_back(std::move(m));
  }
}

}  // namespace

// tinyobjloader reads "v 1 abc 0" as (1, 0, 0) without a word: every number of a v, vn or vt line
// is checked here first, so that a corrupt file is an error at its line, not a silently wrong mesh.
void check_obj_numbers(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    std::istringstream ss(line);
    std::string tag, word;
    ss >> tag;
    if (tag != "v" && tag != "vn" && tag != "vt") continue;
    const char* kind = tag == "v" ? "vertex position" : tag == "vn" ? "vertex normal" : "vertex texture coordinate";
    int count = 0;
    while (ss >> word && word[0] != '#') {
      char* end = nullptr;
      const float v = std::strtof(word.c_str(), &end);
      if (end != word.c_str() + word.size() || !std::isfinite(v))
        throw SceneError(path, n, fmt::format("{} ('{}'): '{}' is not a finite number", kind, tag, word));
      ++count;
    }
    if (count < (tag == "vt" ? 1 : 3))
      throw SceneError(path, n, fmt::format("{} ('{}'): {} number(s), expected {}", kind, tag, count, tag == "vt" ? "1 to 3" : "3"));
  }
}

void import_obj(const std::string& path, const MeshImport& opt, Scene& scene, std::vector<TriangleMesh>& out) {
  std::string dir = fs::path(path).parent_path().string();
  if (std::ifstream(path)) check_obj_numbers(path);  // an unreadable file: tinyobjloader's error below
  tinyobj::ObjReaderConfig cfg;
  cfg.triangulate = true;
  cfg.vertex_color = false;
  cfg.mtl_search_path = dir;
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(path, cfg)) throw SceneError(path, 0, "cannot read OBJ: " + one_line(reader.Error()));
  if (!reader.Warning().empty()) std::fprintf(stderr, "%s: warning: %s\n", path.c_str(), one_line(reader.Warning()).c_str());
  const tinyobj::attrib_t& at = reader.GetAttrib();
  const auto& mats = reader.GetMaterials();
  const ObjMaterials materials = import_obj_materials(mats, dir, path, opt, scene);
  for (const tinyobj::shape_t& sh : reader.GetShapes()) {
    std::map<int, ObjGroup> groups = group_obj_shape(sh, at, mats.size(), path);
    add_obj_meshes(groups, sh, materials, path, opt, out);
  }
}

namespace {

// Reads accessor `ai` as `ncomp` floats per element (float, or normalized unsigned byte/short).
std::vector<float> read_accessor(const tinygltf::Model& model, int ai, int ncomp, const std::string& path) {
  if (ai < 0 || ai >= int(model.accessors.size())) throw SceneError(path, 0, "glTF: bad accessor index");
  const tinygltf::Accessor& a = model.accessors[size_t(ai)];
  if (tinygltf::GetNumComponentsInType(uint32_t(a.type)) != ncomp)
    throw SceneError(path, 0, "glTF: accessor " + std::to_string(ai) + " has the wrong number of components");
  if (a.bufferView < 0 || a.bufferView >= int(model.bufferViews.size())) throw SceneError(path, 0, "glTF: sparse/empty accessors are not supported");
  const tinygltf::BufferView& bv = model.bufferViews[size_t(a.bufferView)];
  if (bv.buffer < 0 || bv.buffer >= int(model.buffers.size())) throw SceneError(path, 0, "glTF: bad buffer index");
  const std::vector<unsigned char>& buf = model.buffers[size_t(bv.buffer)].data;
  int csize = tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType));
  if (csize <= 0) throw SceneError(path, 0, "glTF: bad component type");
  size_t stride = bv.byteStride ? bv.byteStride : size_t(csize * ncomp);
  size_t base = bv.byteOffset + a.byteOffset;
  if (a.count > 0 && base + (a.count - 1) * stride + size_t(csize * ncomp) > buf.size())
    throw SceneError(path, 0, "glTF: accessor " + std::to_string(ai) + " runs past the end of its buffer");
  std::vector<float> r(a.count * size_t(ncomp));
  for (size_t i = 0; i < a.count; ++i)
    for (int c = 0; c < ncomp; ++c) {
      const unsigned char* p = &buf[base + i * stride + size_t(c * csize)];
      float v;
      switch (a.componentType) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: std::memcpy(&v, p, 4); break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: v = p[0] / 255.0f; break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t u; std::memcpy(&u, p, 2); v = u / 65535.0f; break; }
        default: throw SceneError(path, 0, "glTF: unsupported component type for vertex data");
      }
      r[i * size_t(ncomp) + size_t(c)] = v;
    }
  return r;
}

std::vector<uint32_t> read_indices(const tinygltf::Model& model, int ai, const std::string& path) {
  const tinygltf::Accessor& a = model.accessors.at(size_t(ai));
  if (a.bufferView < 0 || a.bufferView >= int(model.bufferViews.size())) throw SceneError(path, 0, "glTF: bad index accessor");
  const tinygltf::BufferView& bv = model.bufferViews[size_t(a.bufferView)];
  const std::vector<unsigned char>& buf = model.buffers.at(size_t(bv.buffer)).data;
  int csize = tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType));
  size_t stride = bv.byteStride ? bv.byteStride : size_t(csize);
  size_t base = bv.byteOffset + a.byteOffset;
  if (csize <= 0 || (a.count > 0 && base + (a.count - 1) * stride + size_t(csize) > buf.size()))
    throw SceneError(path, 0, "glTF: index accessor runs past the end of its buffer");
  std::vector<uint32_t> r(a.count);
  for (size_t i = 0; i < a.count; ++i) {
    const unsigned char* p = &buf[base + i * stride];
    switch (a.componentType) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: r[i] = p[0]; break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t u; std::memcpy(&u, p, 2); r[i] = u; break; }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t u; std::memcpy(&u, p, 4); r[i] = u; break; }
      default: throw SceneError(path, 0, "glTF: bad index component type");
    }
  }
  return r;
}

Mat4 node_local(const tinygltf::Node& n) {
  Mat4 m;
  if (n.matrix.size() == 16) {  // column-major
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) m.m[r][c] = float(n.matrix[size_t(c * 4 + r)]);
    return m;
  }
  Mat4 t, rot, s;
  if (n.translation.size() == 3) t = translate(Vec3(float(n.translation[0]), float(n.translation[1]), float(n.translation[2])));
  if (n.scale.size() == 3) s = scale(Vec3(float(n.scale[0]), float(n.scale[1]), float(n.scale[2])));
  if (n.rotation.size() == 4) {
    float x = float(n.rotation[0]), y = float(n.rotation[1]), z = float(n.rotation[2]), w = float(n.rotation[3]);
    rot.m[0][0] = 1 - 2 * (y * y + z * z); rot.m[0][1] = 2 * (x * y - z * w); rot.m[0][2] = 2 * (x * z + y * w);
    rot.m[1][0] = 2 * (x * y + z * w); rot.m[1][1] = 1 - 2 * (x * x + z * z); rot.m[1][2] = 2 * (y * z - x * w);
    rot.m[2][0] = 2 * (x * z - y * w); rot.m[2][1] = 2 * (y * z + x * w); rot.m[2][2] = 1 - 2 * (x * x + y * y);
  }
  return t * rot * s;
}

struct GltfCtx {
  const tinygltf::Model& model;
  const std::string& path;
  const MeshImport& opt;
  Scene& scene;
  std::vector<TriangleMesh>& out;
  std::vector<int> mat_index;
  std::vector<std::optional<AreaEmission>> mat_emit;
  std::optional<CameraKey>* camera;
  int depth = 0;
};

void visit_node(GltfCtx& c, int ni, const Mat4& parent) {
  if (ni < 0 || ni >= int(c.model.nodes.size()) || ++c.depth > 256) throw SceneError(c.path, 0, "glTF: bad node hierarchy");
  const tinygltf::Node& node = c.model.nodes[size_t(ni)];
  Mat4 world = parent * node_local(node);
  if (node.mesh >= 0) {
    if (node.mesh >= int(c.model.meshes.size())) throw SceneError(c.path, 0, "glTF: bad mesh index");
    const tinygltf::Mesh& mesh = c.model.meshes[size_t(node.mesh)];
    for (const tinygltf::Primitive& prim : mesh.primitives) {
      if (prim.mode != -1 && prim.mode != TINYGLTF_MODE_TRIANGLES) {
        std::fprintf(stderr, "%s: warning: mesh '%s': non-triangle primitive skipped\n", c.path.c_str(), mesh.name.c_str());
        continue;
      }
      auto pit = prim.attributes.find("POSITION");
      if (pit == prim.attributes.end()) throw SceneError(c.path, 0, "glTF: primitive without POSITION");
      std::vector<float> pf = read_accessor(c.model, pit->second, 3, c.path);
      std::vector<Vec3> p, n;
      std::vector<Vec2> uv;
      for (size_t i = 0; i + 2 < pf.size(); i += 3) p.emplace_back(pf[i], pf[i + 1], pf[i + 2]);
      if (auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) {
        std::vector<float> nf = read_accessor(c.model, it->second, 3, c.path);
        for (size_t i = 0; i + 2 < nf.size(); i += 3) n.emplace_back(nf[i], nf[i + 1], nf[i + 2]);
      }
      if (auto it = prim.attributes.find("TEXCOORD_0"); it != prim.attributes.end()) {
        std::vector<float> tf = read_accessor(c.model, it->second, 2, c.path);
        for (size_t i = 0; i + 1 < tf.size(); i += 2) uv.emplace_back(tf[i], 1 - tf[i + 1]);
      }
      std::vector<uint32_t> idx;
      if (prim.indices >= 0) idx = read_indices(c.model, prim.indices, c.path);
      else
        for (uint32_t i = 0; i < p.size(); ++i) idx.push_back(i);
      TriangleMesh m;
      try {
        m = make_world_mesh(p, n, uv, idx, c.opt.world_from_object * world, c.opt.reverse_orientation);
      } catch (const std::exception& e) {
        if (located(e)) throw;
        throw SceneError(c.path, 0, "mesh '" + mesh.name + "': " + e.what());
      }
      int mi = prim.material;
      bool file_mat = c.opt.use_file_materials && mi >= 0 && mi < int(c.mat_index.size());
      m.material = file_mat ? c.mat_index[size_t(mi)] : c.opt.material;
      m.emission = c.opt.use_file_materials ? (file_mat ? c.mat_emit[size_t(mi)] : std::nullopt) : c.opt.emission;
      m.source = c.path + ":" + mesh.name;
      c.out.push_back(std::move(m));
    }
  }
  if (node.camera >= 0 && c.camera && !*c.camera && node.camera < int(c.model.cameras.size())) {
    const tinygltf::Camera& cam = c.model.cameras[size_t(node.camera)];
    if (cam.type == "perspective") {
      // glTF: right-handed, camera looks down -z with +y up. pbrt: left-handed camera space, +z
      // forward. Negating z maps the view direction to +z and keeps +x on the image's right.
      Mat4 wfc = c.opt.world_from_object * world, cfw;
      if (!wfc.inverse(cfw)) throw SceneError(c.path, 0, "glTF: singular camera transform");
      CameraKey key;
      key.camera_from_world = scale(Vec3(1, 1, -1)) * cfw;
      double yfov = cam.perspective.yfov, aspect = cam.perspective.aspectRatio;
      double shorter = (aspect > 0 && aspect < 1) ? 2 * std::atan(std::tan(yfov / 2) * aspect) : yfov;
      key.fov_degrees = float(shorter * 180.0 / 3.14159265358979323846);
      if (!(key.fov_degrees > 0 && key.fov_degrees < 180)) throw SceneError(c.path, 0, "glTF: bad camera yfov");
      *c.camera = key;
    }
  }
  for (int ch : node.children) visit_node(c, ch, world);
  --c.depth;
}

Image gltf_image(const tinygltf::Model& model, int tex, const std::string& path) {
  if (tex < 0 || tex >= int(model.textures.size())) throw SceneError(path, 0, "glTF: bad texture index");
  int src = model.textures[size_t(tex)].source;
  if (src < 0 || src >= int(model.images.size())) throw SceneError(path, 0, "glTF: texture without an image");
  const tinygltf::Image& im = model.images[size_t(src)];
  if (!im.image.empty() && im.width > 0 && im.height > 0 && im.component > 0 && (im.bits == 8 || im.bits == 16)) {
    Image out(im.width, im.height);
    size_t bpc = size_t(im.bits / 8), nc = size_t(im.component);
    if (im.image.size() < size_t(im.width) * size_t(im.height) * nc * bpc) throw SceneError(path, 0, "glTF: truncated image data");
    for (int y = 0; y < im.height; ++y)
      for (int x = 0; x < im.width; ++x) {
        float ch[3];
        for (size_t k = 0; k < 3; ++k) {
          size_t kk = std::min(k, nc >= 3 ? k : size_t(0));
          const unsigned char* p = &im.image[((size_t(y) * size_t(im.width) + size_t(x)) * nc + kk) * bpc];
          float v = bpc == 1 ? p[0] / 255.0f : (uint16_t(p[0]) | uint16_t(p[1] << 8)) / 65535.0f;
          ch[k] = srgb_to_linear(v);
        }
        out.at(x, y) = Rgb(ch[0], ch[1], ch[2]);
      }
    return out;
  }
  if (!im.uri.empty() && im.uri.rfind("data:", 0) != 0)
    return read_image_for((fs::path(path).parent_path() / im.uri).string(), path, 0);
  throw SceneError(path, 0, "glTF: image " + std::to_string(src) + " could not be decoded");
}

}  // namespace

void import_gltf(const std::string& path, const MeshImport& opt, Scene& scene, std::vector<TriangleMesh>& out,
                 std::optional<CameraKey>* camera) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  std::string ext = fs::path(path).extension().string();
  for (char& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
  bool ok = ext == ".glb" ? loader.LoadBinaryFromFile(&model, &err, &warn, path)
                          : loader.LoadASCIIFromFile(&model, &err, &warn, path);
  // glTF 1.0 (objects keyed by id) is not glTF 2.0: tinygltf reads it as empty or fails with its own
  // words. Say which version it is and what to do (the version comes from tinygltf or the JSON).
  std::string version = model.asset.version;
  if (!ok && ext != ".glb") {
    std::ifstream in(path);
    const auto j = nlohmann::json::parse(in, nullptr, false);
    if (j.is_object() && j.contains("asset") && j["asset"].is_object() && j["asset"].value("version", "") != "")
      version = j["asset"]["version"].get<std::string>();
  }
  if (version.starts_with("1"))
    throw SceneError(path, 0, "glTF " + version + " is not supported: restir-lab reads glTF 2.0 (convert the file, e.g. with Blender's glTF importer and exporter)");
  if (!ok) throw SceneError(path, 0, "cannot read glTF: " + one_line(err.empty() ? warn : err));
  if (!warn.empty()) std::fprintf(stderr, "%s: warning: %s\n", path.c_str(), one_line(warn).c_str());

  // External buffers and images are inputs too (never written onto, part of a study's hash).
  for (const auto& b : model.buffers)
    if (!b.uri.empty() && !b.uri.starts_with("data:")) scene.input_files.push_back((fs::path(path).parent_path() / b.uri).string());
  for (const auto& im : model.images)
    if (!im.uri.empty() && !im.uri.starts_with("data:")) scene.input_files.push_back((fs::path(path).parent_path() / im.uri).string());
  GltfCtx c{model, path, opt, scene, out, {}, {}, camera};
  if (opt.use_file_materials) {
    for (const tinygltf::Material& gm : model.materials) {
      Material m;
      m.name = gm.name;
      const auto& pbr = gm.pbrMetallicRoughness;
      Rgb base(1);
      if (pbr.baseColorFactor.size() >= 3)
        base = Rgb(float(pbr.baseColorFactor[0]), float(pbr.baseColorFactor[1]), float(pbr.baseColorFactor[2]));
      m.reflectance = base;
      if (pbr.baseColorTexture.index >= 0) {
        Texture t;
        t.kind = Texture::Kind::image;
        t.name = gm.name + ".baseColor";
        t.image = gltf_image(model, pbr.baseColorTexture.index, path);
        for (Rgb& px : t.image.pixels) px *= base;
        scene.textures.push_back(std::move(t));
        m.reflectance_texture = int(scene.textures.size()) - 1;
      }
      if (pbr.metallicFactor > 0.5) {
        m.type = Material::Type::conductor;
        m.use_reflectance = true;
        m.alpha_x = m.alpha_y = float(pbr.roughnessFactor * pbr.roughnessFactor);
      }
      Rgb e(0);
      if (gm.emissiveFactor.size() >= 3)
        e = Rgb(float(gm.emissiveFactor[0]), float(gm.emissiveFactor[1]), float(gm.emissiveFactor[2]));
      if (auto it = gm.extensions.find("KHR_materials_emissive_strength"); it != gm.extensions.end())
        if (it->second.Has("emissiveStrength")) e *= float(it->second.Get("emissiveStrength").GetNumberAsDouble());
      // A negative or non-finite emission is not "no emission": refuse it rather than drop it.
      if (!is_finite(e) || e.x < 0 || e.y < 0 || e.z < 0)
        throw SceneError(path, 0, "material '" + gm.name + "': emissiveFactor (x emissiveStrength) must be finite and >= 0");
      c.mat_emit.push_back(max_component(e) > 0 ? std::optional<AreaEmission>(AreaEmission{e, gm.doubleSided}) : std::nullopt);
      scene.materials.push_back(m);
      c.mat_index.push_back(int(scene.materials.size()) - 1);
    }
  }
  std::vector<int> roots;
  int si = model.defaultScene >= 0 ? model.defaultScene : 0;
  if (si < int(model.scenes.size())) {
    roots = model.scenes[size_t(si)].nodes;
  } else {  // no scenes: every node that is nobody's child
    std::vector<bool> child(model.nodes.size());
    for (const auto& n : model.nodes)
      for (int ch : n.children)
        if (ch >= 0 && ch < int(child.size())) child[size_t(ch)] = true;
    for (size_t i = 0; i < child.size(); ++i)
      if (!child[i]) roots.push_back(int(i));
  }
  for (int r : roots) visit_node(c, r, Mat4::identity());
}

}  // namespace rl::detail
