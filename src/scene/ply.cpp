#include "scene/ply.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <sstream>

#include "scene/loader.h"

namespace rl {
namespace {

enum class PType { i8, u8, i16, u16, i32, u32, f32, f64, invalid };

PType parse_ptype(const std::string& s) {
  if (s == "char" || s == "int8") return PType::i8;
  if (s == "uchar" || s == "uint8") return PType::u8;
  if (s == "short" || s == "int16") return PType::i16;
  if (s == "ushort" || s == "uint16") return PType::u16;
  if (s == "int" || s == "int32") return PType::i32;
  if (s == "uint" || s == "uint32") return PType::u32;
  if (s == "float" || s == "float32") return PType::f32;
  if (s == "double" || s == "float64") return PType::f64;
  return PType::invalid;
}

int ptype_size(PType t) {
  switch (t) {
    case PType::i8: case PType::u8: return 1;
    case PType::i16: case PType::u16: return 2;
    case PType::i32: case PType::u32: case PType::f32: return 4;
    case PType::f64: return 8;
    default: return 0;
  }
}

struct Property {
  std::string name;
  PType type = PType::f32;
  bool is_list = false;
  PType count_type = PType::u8;
};

struct Element {
  std::string name;
  size_t count = 0;
  std::vector<Property> props;
};

enum class Format { ascii, binary_le, binary_be };

class Reader {
 public:
  Reader(const std::string& path, std::istream& in, Format f, int line) : path_(path), in_(in), fmt_(f), line_(line) {}

  double read(PType t) {
    if (fmt_ == Format::ascii) return read_ascii();
    unsigned char b[8];
    int n = ptype_size(t);
    if (!in_.read(reinterpret_cast<char*>(b), n)) throw SceneError(path_, 0, "unexpected end of binary data");
    bool little = true;
    {
      uint16_t one = 1;
      unsigned char c;
      std::memcpy(&c, &one, 1);
      little = c == 1;
    }
    bool file_le = fmt_ == Format::binary_le;
    if (little != file_le) std::reverse(b, b + n);
    switch (t) {
      case PType::i8: { int8_t v; std::memcpy(&v, b, 1); return v; }
      case PType::u8: return b[0];
      case PType::i16: { int16_t v; std::memcpy(&v, b, 2); return v; }
      case PType::u16: { uint16_t v; std::memcpy(&v, b, 2); return v; }
      case PType::i32: { int32_t v; std::memcpy(&v, b, 4); return v; }
      case PType::u32: { uint32_t v; std::memcpy(&v, b, 4); return v; }
      case PType::f32: { float v; std::memcpy(&v, b, 4); return v; }
      case PType::f64: { double v; std::memcpy(&v, b, 8); return v; }
      default: return 0;
    }
  }
  // ASCII: one element per line; tokens are read line by line so errors name the line.
  void begin_element() {
    if (fmt_ != Format::ascii) return;
    std::string s;
    do {
      if (!std::getline(in_, s)) throw SceneError(path_, line_ + 1, "unexpected end of file (more elements declared)");
      ++line_;
    } while (s.find_first_not_of(" \t\r") == std::string::npos);
    ls_.clear();
    ls_.str(s);
  }
  int line() const { return line_; }

 private:
  double read_ascii() {
    std::string tok;
    if (!(ls_ >> tok)) throw SceneError(path_, line_, "too few values on line");
    try {
      size_t pos = 0;
      double v = std::stod(tok, &pos);
      if (pos != tok.size()) throw std::invalid_argument(tok);
      return v;
    } catch (const std::exception&) {
      throw SceneError(path_, line_, "bad number '" + tok + "'");
    }
  }
  const std::string& path_;
  std::istream& in_;
  Format fmt_;
  int line_;
  std::istringstream ls_;
};

struct Header {
  Format fmt = Format::ascii;
  std::vector<Element> elements;
  int lineno = 0;  // the header's last line (end_header)
};

Format parse_format(std::istringstream& ls, const std::string& path, int lineno) {
  std::string f, ver;
  ls >> f >> ver;
  if (f == "ascii") return Format::ascii;
  if (f == "binary_little_endian") return Format::binary_le;
  if (f == "binary_big_endian") return Format::binary_be;
  throw SceneError(path, lineno, "unknown PLY format '" + f + "'");
}

Property parse_property(std::istringstream& ls, const std::string& path, int lineno) {
  Property p;
  std::string t;
  ls >> t;
  if (t == "list") {
    std::string ct, it;
    ls >> ct >> it >> p.name;
    p.is_list = true;
    p.count_type = parse_ptype(ct);
    p.type = parse_ptype(it);
    if (p.count_type == PType::invalid || p.type == PType::invalid || p.count_type == PType::f32 ||
        p.count_type == PType::f64)
      throw SceneError(path, lineno, "bad list property types '" + ct + " " + it + "'");
  } else {
    ls >> p.name;
    p.type = parse_ptype(t);
    if (p.type == PType::invalid) throw SceneError(path, lineno, "unknown property type '" + t + "'");
  }
  if (p.name.empty()) throw SceneError(path, lineno, "property without a name");
  return p;
}

Header read_header(const std::string& path, std::istream& in) {
  Header h;
  std::string line;
  int& lineno = h.lineno;
  auto next_line = [&]() -> bool {
    if (!std::getline(in, line)) return false;
    ++lineno;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return true;
  };
  if (!next_line() || line != "ply") throw SceneError(path, 1, "not a PLY file (missing 'ply' magic)");
  bool have_format = false;
  for (;;) {
    if (!next_line()) throw SceneError(path, lineno, "unexpected end of file in PLY header");
    std::istringstream ls(line);
    std::string kw;
    ls >> kw;
    if (kw.empty() || kw == "comment" || kw == "obj_info") continue;
    if (kw == "end_header") break;
    if (kw == "format") {
      h.fmt = parse_format(ls, path, lineno);
      have_format = true;
    } else if (kw == "element") {
      Element e;
      long long count = -1;
      ls >> e.name >> count;
      if (e.name.empty() || count < 0) throw SceneError(path, lineno, "malformed element line");
      e.count = size_t(count);
      h.elements.push_back(e);
    } else if (kw == "property") {
      if (h.elements.empty()) throw SceneError(path, lineno, "property before any element");
      h.elements.back().props.push_back(parse_property(ls, path, lineno));
    } else {
      throw SceneError(path, lineno, "unknown PLY header keyword '" + kw + "'");
    }
  }
  if (!have_format) throw SceneError(path, lineno, "PLY header has no format line");
  return h;
}

// Every element takes at least one byte: reject absurd counts before allocating for them.
void check_element_counts(const std::string& path, std::istream& in, const std::vector<Element>& elements) {
  std::streampos here = in.tellg();
  in.seekg(0, std::ios::end);
  std::streamoff remaining = in.tellg() - here;
  in.seekg(here);
  for (const Element& e : elements)
    if (e.count > 0 && std::streamoff(e.count) > remaining)
      throw SceneError(path, 0, "element '" + e.name + "' declares " + std::to_string(e.count) +
                                    " entries, more than the file can hold");
}

double read_list_length(Reader& rd, const Property& p, const std::string& path) {
  double c = rd.read(p.count_type);
  if (c < 0 || c > 1e6) throw SceneError(path, rd.line(), "bad list length");
  return c;
}

void skip_list(Reader& rd, const Property& p, const std::string& path) {
  double c = read_list_length(rd, p, path);
  for (int j = 0; j < int(c); ++j) rd.read(p.type);
}

// Positions of the vertex properties that the mesh keeps (-1: absent).
struct VertexColumns {
  int x = -1, y = -1, z = -1, nx = -1, ny = -1, nz = -1, u = -1, v = -1;
};

VertexColumns vertex_columns(const Element& e, const std::string& path) {
  VertexColumns c;
  for (size_t i = 0; i < e.props.size(); ++i) {
    const std::string& n = e.props[i].name;
    int k = int(i);
    if (e.props[i].is_list) continue;
    if (n == "x") c.x = k;
    else if (n == "y") c.y = k;
    else if (n == "z") c.z = k;
    else if (n == "nx") c.nx = k;
    else if (n == "ny") c.ny = k;
    else if (n == "nz") c.nz = k;
    else if (n == "u" || n == "s" || n == "texture_u" || n == "texture_s") c.u = k;
    else if (n == "v" || n == "t" || n == "texture_v" || n == "texture_t") c.v = k;
  }
  if (c.x < 0 || c.y < 0 || c.z < 0) throw SceneError(path, 0, "vertex element lacks x, y or z");
  return c;
}

void read_vertices(const Element& e, Reader& rd, const std::string& path, PlyMesh& mesh) {
  const VertexColumns c = vertex_columns(e, path);
  bool has_n = c.nx >= 0 && c.ny >= 0 && c.nz >= 0, has_uv = c.u >= 0 && c.v >= 0;
  mesh.positions.resize(e.count);
  if (has_n) mesh.normals.resize(e.count);
  if (has_uv) mesh.uvs.resize(e.count);
  std::vector<double> vals(e.props.size());
  auto at = [&](int k) { return float(vals[size_t(k)]); };
  for (size_t v = 0; v < e.count; ++v) {
    rd.begin_element();
    for (size_t i = 0; i < e.props.size(); ++i) {
      const Property& p = e.props[i];
      if (p.is_list) {
        skip_list(rd, p, path);
        vals[i] = 0;
      } else {
        vals[i] = rd.read(p.type);
      }
    }
    mesh.positions[v] = Vec3(at(c.x), at(c.y), at(c.z));
    if (has_n) mesh.normals[v] = Vec3(at(c.nx), at(c.ny), at(c.nz));
    if (has_uv) mesh.uvs[v] = Vec2(at(c.u), at(c.v));
  }
}

// Polygon f's vertex indices (list property p), each checked against the vertices read.
void read_polygon(Reader& rd, const Property& p, const std::string& path, size_t f, size_t vertices,
                  std::vector<uint32_t>& poly) {
  double c = read_list_length(rd, p, path);
  poly.clear();
  for (int j = 0; j < int(c); ++j) {
    double x = rd.read(p.type);
    if (x < 0 || x >= double(vertices))
      throw SceneError(path, rd.line(), "face " + std::to_string(f) + ": vertex index " +
                                            std::to_string((long long)x) + " out of range");
    poly.push_back(uint32_t(x));
  }
  if (poly.size() < 3) throw SceneError(path, rd.line(), "face " + std::to_string(f) + " has fewer than 3 vertices");
}

void read_faces(const Element& e, Reader& rd, const std::string& path, PlyMesh& mesh) {
  int ii = -1;
  for (size_t i = 0; i < e.props.size(); ++i)
    if (e.props[i].is_list && (e.props[i].name == "vertex_indices" || e.props[i].name == "vertex_index")) ii = int(i);
  if (ii < 0) throw SceneError(path, 0, "face element lacks a vertex_indices list");
  std::vector<uint32_t> poly;
  for (size_t f = 0; f < e.count; ++f) {
    rd.begin_element();
    for (size_t i = 0; i < e.props.size(); ++i) {
      const Property& p = e.props[i];
      if (!p.is_list) {
        rd.read(p.type);
        continue;
      }
      if (int(i) != ii) {
        skip_list(rd, p, path);
        continue;
      }
      read_polygon(rd, p, path, f, mesh.positions.size(), poly);
      for (size_t j = 1; j + 1 < poly.size(); ++j) {  // fan: quads -> (0,1,2), (0,2,3)
        mesh.indices.push_back(poly[0]);
        mesh.indices.push_back(poly[j]);
        mesh.indices.push_back(poly[j + 1]);
      }
    }
  }
}

void skip_element(const Element& e, Reader& rd, const std::string& path) {
  for (size_t k = 0; k < e.count; ++k) {
    rd.begin_element();
    for (const Property& p : e.props) {
      if (p.is_list) skip_list(rd, p, path);
      else rd.read(p.type);
    }
  }
}

}  // namespace

PlyMesh read_ply(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path, 0, "cannot open PLY file");
  const Header h = read_header(path, in);
  check_element_counts(path, in, h.elements);
  PlyMesh mesh;
  bool have_vertices = false, have_faces = false;
  Reader rd(path, in, h.fmt, h.lineno);
  for (const Element& e : h.elements) {
    if (e.name == "vertex") {
      have_vertices = true;
      read_vertices(e, rd, path, mesh);
    } else if (e.name == "face") {
      have_faces = true;
      read_faces(e, rd, path, mesh);
    } else {
      skip_element(e, rd, path);
    }
  }
  if (!have_vertices) throw SceneError(path, 0, "PLY file has no vertex element");
  if (!have_faces) throw SceneError(path, 0, "PLY file has no face element");
  return mesh;
}

}  // namespace rl
