#include "scene/pbrt_tokenizer.h"

#include <fmt/format.h>

#include <algorithm>
#include <cfloat>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/suggest.h"

namespace rl::pbrt {

void warn(const Token& t, const std::string& msg) {
  std::fprintf(stderr, "%s:%d: warning: %s\n", t.file ? t.file->c_str() : "?", t.line, msg.c_str());
}

void Tokenizer::push_file(const std::string& path, const std::string& from_file, int from_line) {
  if (stack_.size() > 64) throw SceneError(from_file, from_line, "Include nesting too deep (recursive Include?)");
  std::error_code ec;
  // An ifstream opens a directory without complaint on Linux and then reads nothing.
  if (std::filesystem::is_directory(path, ec))
    throw SceneError(from_file, from_line, "'" + path + "' is a directory, not a scene file");
  // A FIFO or a device (/dev/zero, /dev/stdin) would block or never end.
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    throw SceneError(from_file, from_line, "'" + path + "' is not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(from_file, from_line, "cannot open file '" + path + "'");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw SceneError(from_file, from_line, "cannot read file '" + path + "'");
  Source s;
  s.file = std::make_shared<const std::string>(path);
  s.text = ss.str();
  if (s.text.starts_with("\xEF\xBB\xBF")) s.pos = 3;  // UTF-8 byte-order mark (editors on Windows add one)
  if (s.text.find('\0') != std::string::npos)
    throw SceneError(path, 1 + int(std::count(s.text.begin(), s.text.begin() + std::ptrdiff_t(s.text.find('\0')), '\n')),
                     "NUL byte: this is a binary file, not a pbrt scene");
  files_.push_back(path);
  stack_.push_back(std::move(s));
  peeked_.reset();
}

const std::string& Tokenizer::current_file() const {
  static const std::string none = "?";
  if (!stack_.empty()) return *stack_.back().file;
  return last_file_ ? *last_file_ : none;
}

Token Tokenizer::next() {
  if (peeked_) {
    Token t = std::move(*peeked_);
    peeked_.reset();
    return t;
  }
  return scan();
}

const Token& Tokenizer::peek() {
  if (!peeked_) peeked_ = scan();
  return *peeked_;
}

Token Tokenizer::scan() {
  while (!stack_.empty()) {
    Source& s = stack_.back();
    const std::string& t = s.text;
    while (s.pos < t.size()) {
      char c = t[s.pos];
      if (c == '\n') {
        ++s.line;
        ++s.pos;
      } else if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
        ++s.pos;
      } else if (c == '#') {
        while (s.pos < t.size() && t[s.pos] != '\n') ++s.pos;
      } else {
        break;
      }
    }
    if (s.pos >= t.size()) {
      last_file_ = s.file;
      last_line_ = s.line;
      stack_.pop_back();
      continue;
    }
    Token tok;
    tok.file = s.file;
    tok.line = s.line;
    char c = t[s.pos];
    if (c == '[' || c == ']') {
      tok.kind = c == '[' ? Token::Kind::lbracket : Token::Kind::rbracket;
      tok.text = std::string(1, c);
      ++s.pos;
      return tok;
    }
    if (c == '"') {
      tok.kind = Token::Kind::string;
      ++s.pos;
      std::string v;
      for (;;) {
        if (s.pos >= t.size() || t[s.pos] == '\n') tok.fail("unterminated string");
        char d = t[s.pos++];
        if (d == '"') break;
        if (d == '\\' && s.pos < t.size()) {
          char e = t[s.pos++];
          switch (e) {
            case 'n': v += '\n'; break;
            case 't': v += '\t'; break;
            default: v += e;
          }
          continue;
        }
        v += d;
      }
      tok.text = std::move(v);
      return tok;
    }
    tok.kind = Token::Kind::word;
    size_t b = s.pos;
    while (s.pos < t.size()) {
      char d = t[s.pos];
      if (d == ' ' || d == '\t' || d == '\n' || d == '\r' || d == '"' || d == '[' || d == ']' || d == '#') break;
      ++s.pos;
    }
    tok.text = t.substr(b, s.pos - b);
    return tok;
  }
  Token eof;
  eof.kind = Token::Kind::eof;
  eof.file = last_file_;
  eof.line = last_line_;
  return eof;
}

static bool parse_number(const std::string& s, double& out) {
  const char* b = s.data();
  const char* e = b + s.size();
  if (b != e && *b == '+') ++b;
  auto r = std::from_chars(b, e, out);
  // out_of_range (1e400) is a number, just not a finite one: reported by the finiteness check.
  if (r.ec == std::errc::result_out_of_range && r.ptr == e) {
    out = (*b == '-') ? -HUGE_VAL : HUGE_VAL;
    return true;
  }
  return r.ec == std::errc() && r.ptr == e;
}

// Every number a scene hands the renderer is stored as a float: NaN, infinities and values beyond
// FLT_MAX (which become infinities) are meaningless for every parameter.
static void check_finite_number(const Token& v, const std::string& decl, double d) {
  if (!std::isfinite(d) || std::fabs(d) > double(FLT_MAX))
    v.fail("parameter \"" + decl + "\": value '" + v.text + "' is not a finite number");
}

static std::string canonical_type(const std::string& t) {
  if (t == "point") return "point3";
  if (t == "vector") return "vector3";
  if (t == "normal3") return "normal";
  if (t == "color") return "rgb";
  return t;
}

ParamList parse_params(Tokenizer& tok) {
  ParamList list;
  while (tok.peek().kind == Token::Kind::string) {
    Token decl = tok.next();
    std::istringstream ds(decl.text);
    std::string type, name, extra;
    ds >> type >> name >> extra;
    if (type.empty() || name.empty() || !extra.empty())
      decl.fail("malformed parameter declaration \"" + decl.text + "\" (expected \"type name\")");
    type = canonical_type(type);
    static const char* kTypes[] = {"integer", "float", "point2", "vector2", "point3", "vector3", "normal", "rgb",
                                   "spectrum", "bool", "string", "texture", "blackbody"};
    bool known = false;
    for (const char* k : kTypes) known = known || type == k;
    if (!known) decl.fail("unknown parameter type '" + type + "' in \"" + decl.text + "\"");
    Param p;
    p.type = type;
    p.name = name;
    p.file = decl.file;
    p.line = decl.line;
    std::vector<Token> values;
    if (tok.peek().kind == Token::Kind::lbracket) {
      Token open = tok.next();
      for (;;) {
        Token v = tok.next();
        if (v.kind == Token::Kind::rbracket) break;
        if (v.kind == Token::Kind::eof) open.fail("unterminated '[' for parameter \"" + decl.text + "\"");
        if (v.kind == Token::Kind::lbracket) v.fail("nested '[' in parameter \"" + decl.text + "\"");
        values.push_back(std::move(v));
      }
    } else {
      const Token& v = tok.peek();
      double dummy;
      bool ok = v.kind == Token::Kind::string ||
                (v.kind == Token::Kind::word && (parse_number(v.text, dummy) || v.text == "true" || v.text == "false"));
      if (!ok) decl.fail("missing value for parameter \"" + decl.text + "\"");
      values.push_back(tok.next());
    }
    if (values.empty()) decl.fail("empty value list for parameter \"" + decl.text + "\"");
    bool want_strings = type == "string" || type == "texture";
    bool want_bool = type == "bool";
    bool either = type == "spectrum";
    for (const Token& v : values) {
      if (want_bool) {
        if (v.text == "true") p.nums.push_back(1);
        else if (v.text == "false") p.nums.push_back(0);
        else v.fail("parameter \"" + decl.text + "\": expected true or false, got '" + v.text + "'");
      } else if (v.kind == Token::Kind::string && (want_strings || either)) {
        p.strs.push_back(v.text);
      } else if (v.kind == Token::Kind::word && !want_strings) {
        double d;
        if (!parse_number(v.text, d)) v.fail("parameter \"" + decl.text + "\": expected a number, got '" + v.text + "'");
        check_finite_number(v, decl.text, d);
        p.nums.push_back(d);
      } else {
        v.fail("parameter \"" + decl.text + "\": expected " + std::string(want_strings ? "a quoted string" : "a number") +
               ", got '" + v.text + "'");
      }
    }
    if (!p.strs.empty() && !p.nums.empty()) decl.fail("parameter \"" + decl.text + "\" mixes strings and numbers");
    for (const Param& q : list.params)
      if (q.name == p.name) decl.fail("parameter '" + p.name + "' given twice");
    list.params.push_back(std::move(p));
  }
  return list;
}

const Param* ParamList::find(const std::string& name) const {
  if (std::find(asked_.begin(), asked_.end(), name) == asked_.end()) asked_.push_back(name);
  for (const Param& p : params)
    if (p.name == name) {
      p.used = true;
      return &p;
    }
  return nullptr;
}

static const Param* typed(const ParamList& l, const std::string& name, std::initializer_list<const char*> types) {
  const Param* p = l.find(name);
  if (!p) return nullptr;
  for (const char* t : types)
    if (p->type == t) return p;
  std::string want;
  for (const char* t : types) want += (want.empty() ? "" : " or ") + std::string(t);
  p->fail("has type '" + p->type + "', expected " + want);
}

static void expect_count(const Param& p, size_t n) {
  size_t have = p.nums.size() + p.strs.size();
  if (have != n) p.fail("expected " + std::to_string(n) + " value(s), got " + std::to_string(have));
}

// Converting a double outside int's range to int is undefined behaviour: check first.
static void check_int(const Param& p, double d) {
  if (d < double(INT_MIN) || d > double(INT_MAX)) p.fail(fmt::format("value {} is out of the integer range", d));
  if (d != std::floor(d)) p.fail(fmt::format("value {} is not an integer", d));
}

std::string format_number(double v) { return fmt::format("{}", v); }

void ParamList::check_range(const std::string& name, double lo, double hi, bool lo_open) const {
  if (std::find(asked_.begin(), asked_.end(), name) == asked_.end()) asked_.push_back(name);
  const Param* p = nullptr;
  for (const Param& q : params)
    if (q.name == name) p = &q;
  if (!p || p->type == "blackbody") return;  // blackbody: the temperature has its own check
  for (double d : p->nums) {
    bool below = lo_open ? !(d > lo) : !(d >= lo);
    if (below || d > hi) {
      std::string range = std::string(lo_open ? "(" : "[") + format_number(lo) + ", " +
                          (std::isinf(hi) ? std::string("inf)") : format_number(hi) + "]");
      p->fail(fmt::format("value {} is out of range {}", format_number(d), range));
    }
  }
}

float ParamList::get_float(const std::string& name, float def) const {
  const Param* p = typed(*this, name, {"float"});
  if (!p) return def;
  expect_count(*p, 1);
  return float(p->nums[0]);
}

int ParamList::get_int(const std::string& name, int def) const {
  const Param* p = typed(*this, name, {"integer"});
  if (!p) return def;
  expect_count(*p, 1);
  check_int(*p, p->nums[0]);
  return int(p->nums[0]);
}

bool ParamList::get_bool(const std::string& name, bool def) const {
  const Param* p = typed(*this, name, {"bool"});
  if (!p) return def;
  expect_count(*p, 1);
  return p->nums[0] != 0;
}

std::string ParamList::get_string(const std::string& name, const std::string& def) const {
  const Param* p = typed(*this, name, {"string"});
  if (!p) return def;
  expect_count(*p, 1);
  return p->strs[0];
}

std::optional<std::string> ParamList::get_texture(const std::string& name) const {
  const Param* p = typed(*this, name, {"texture"});
  if (!p) return std::nullopt;
  expect_count(*p, 1);
  return p->strs[0];
}

std::vector<float> ParamList::get_floats(const std::string& name) const {
  const Param* p = typed(*this, name, {"float"});
  std::vector<float> r;
  if (p)
    for (double d : p->nums) r.push_back(float(d));
  return r;
}

std::vector<int> ParamList::get_ints(const std::string& name) const {
  const Param* p = typed(*this, name, {"integer"});
  std::vector<int> r;
  if (p)
    for (double d : p->nums) {
      check_int(*p, d);
      r.push_back(int(d));
    }
  return r;
}

static std::vector<Vec3> triples(const Param* p) {
  std::vector<Vec3> r;
  if (!p) return r;
  if (p->nums.size() % 3 != 0) p->fail("number of values (" + std::to_string(p->nums.size()) + ") is not a multiple of 3");
  for (size_t i = 0; i < p->nums.size(); i += 3)
    r.emplace_back(float(p->nums[i]), float(p->nums[i + 1]), float(p->nums[i + 2]));
  return r;
}

std::vector<Vec3> ParamList::get_point3s(const std::string& name) const {
  return triples(typed(*this, name, {"point3"}));
}
std::vector<Vec3> ParamList::get_normals(const std::string& name) const {
  return triples(typed(*this, name, {"normal"}));
}

std::vector<Vec2> ParamList::get_point2s(const std::string& name) const {
  const Param* p = typed(*this, name, {"point2", "float"});
  std::vector<Vec2> r;
  if (!p) return r;
  if (p->nums.size() % 2 != 0) p->fail("number of values is not a multiple of 2");
  for (size_t i = 0; i < p->nums.size(); i += 2) r.emplace_back(float(p->nums[i]), float(p->nums[i + 1]));
  return r;
}

Vec3 ParamList::get_point3(const std::string& name, Vec3 def) const {
  const Param* p = typed(*this, name, {"point3"});
  if (!p) return def;
  expect_count(*p, 3);
  return triples(p)[0];
}

std::optional<Rgb> ParamList::get_rgb(const std::string& name, bool illuminant) const {
  const Param* p = typed(*this, name, {"rgb", "spectrum", "blackbody"});
  if (!p) return std::nullopt;
  if (p->type == "rgb") {
    expect_count(*p, 3);
    return Rgb(float(p->nums[0]), float(p->nums[1]), float(p->nums[2]));
  }
  if (p->type == "blackbody") {
    expect_count(*p, 1);
    if (!illuminant) p->fail("a blackbody spectrum is only allowed for light sources");
    if (!(p->nums[0] > 0)) p->fail("blackbody temperature must be positive");
    return blackbody_rgb(float(p->nums[0]));
  }
  // spectrum
  if (!p->strs.empty()) {
    expect_count(*p, 1);
    if (auto c = named_spectrum_rgb(p->strs[0])) return c;
    p->fail("unsupported named spectrum '" + p->strs[0] +
            "' (supported: metal-{Au,Ag,Al,Cu,CuZn}-{eta,k}; spectrum files are not supported)");
  }
  if (p->nums.size() == 1) return Rgb(float(p->nums[0]));
  if (p->nums.empty()) p->fail("expected a value");
  p->fail("sampled (wavelength, value) spectra are not supported; give a single value, rgb or a named spectrum");
}

void ParamList::ignore(const std::string& name) const { find(name); }

void ParamList::check_unused(const std::string& context) const {
  for (const Param& p : params) {
    if (p.used) continue;
    // A name the reader asked about but does not consume (range-checked only, e.g. a light's
    // "power") is known and unsupported: suggesting the name itself would be no help.
    if (std::find(asked_.begin(), asked_.end(), p.name) != asked_.end())
      p.fail("not supported by restir-lab for " + context);
    p.fail("unused or unsupported parameter for " + context + did_you_mean(p.name, asked_));
  }
}

std::vector<std::string> ParamList::unused() const {
  std::vector<std::string> r;
  for (const Param& p : params)
    if (!p.used) r.push_back(p.type + " " + p.name);
  return r;
}

// Wyman, Sloan, Shirley 2013, "Simple Analytic Approximations to the CIE XYZ Color Matching
// Functions" (JCGT 2(2)), multi-lobe fit.
static float g(float x, float mu, float s1, float s2) {
  float t = (x - mu) / (x < mu ? s1 : s2);
  return std::exp(-0.5f * t * t);
}

Rgb blackbody_rgb(float kelvin) {
  double X = 0, Y = 0, Z = 0;
  for (int nm = 360; nm <= 830; ++nm) {
    double l = nm * 1e-9;
    const double c = 299792458.0, h = 6.62606957e-34, kb = 1.3806488e-23;
    double le = (2 * h * c * c) / (std::pow(l, 5) * (std::exp((h * c) / (l * kb * kelvin)) - 1));
    float x = float(nm);
    double xb = 1.056 * g(x, 599.8f, 37.9f, 31.0f) + 0.362 * g(x, 442.0f, 16.0f, 26.7f) - 0.065 * g(x, 501.1f, 20.4f, 26.2f);
    double yb = 0.821 * g(x, 568.8f, 46.9f, 40.5f) + 0.286 * g(x, 530.9f, 16.3f, 31.1f);
    double zb = 1.217 * g(x, 437.0f, 11.8f, 36.0f) + 0.681 * g(x, 459.0f, 26.0f, 13.8f);
    X += le * xb;
    Y += le * yb;
    Z += le * zb;
  }
  X /= Y;
  Z /= Y;
  Y = 1;
  Rgb rgb(float(3.2404542 * X - 1.5371385 * Y - 0.4985314 * Z), float(-0.9692660 * X + 1.8760108 * Y + 0.0415560 * Z),
          float(0.0556434 * X - 0.2040259 * Y + 1.0572252 * Z));
  rgb = max(rgb, Rgb(0));
  return rgb / luminance(rgb);
}

std::optional<Rgb> named_spectrum_rgb(const std::string& n) {
  // RGB fits of the measured complex IORs (the values Mitsuba/pbrt-v3 exporters commonly use).
  struct E {
    const char* name;
    Rgb v;
  };
  static const E table[] = {
      {"metal-Cu-eta", {0.200438f, 0.924033f, 1.102212f}}, {"metal-Cu-k", {3.912949f, 2.452848f, 2.142188f}},
      {"metal-Au-eta", {0.143119f, 0.374957f, 1.442479f}}, {"metal-Au-k", {3.983160f, 2.385721f, 1.603215f}},
      {"metal-Ag-eta", {0.155265f, 0.116723f, 0.138342f}}, {"metal-Ag-k", {4.828181f, 3.122249f, 2.146961f}},
      {"metal-Al-eta", {1.657460f, 0.880369f, 0.521229f}}, {"metal-Al-k", {9.223869f, 6.269523f, 4.837001f}},
      {"metal-CuZn-eta", {0.444f, 0.527f, 1.094f}},        {"metal-CuZn-k", {3.695f, 2.765f, 1.829f}},
  };
  for (const E& e : table)
    if (n == e.name) return e.v;
  return std::nullopt;
}

std::optional<float> named_glass_ior(const std::string& n) {
  struct E {
    const char* name;
    float ior;
  };
  static const E table[] = {{"glass-BK7", 1.5168f}, {"glass-BAF10", 1.6700f}, {"glass-FK51A", 1.4866f},
                            {"glass-LASF9", 1.8503f}, {"glass-F5", 1.6727f},  {"glass-F10", 1.7283f},
                            {"glass-F11", 1.7847f}};
  for (const E& e : table)
    if (n == e.name) return e.ior;
  return std::nullopt;
}

}  // namespace rl::pbrt
