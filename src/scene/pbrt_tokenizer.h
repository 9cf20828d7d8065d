// pbrt-v4 scene-file tokens and parameter lists (internal to the scene loader).
#pragma once
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/math.h"
#include "scene/loader.h"

namespace rl::pbrt {

struct Token {
  enum class Kind { word, string, lbracket, rbracket, eof };
  Kind kind = Kind::eof;
  std::string text;  // strings: without the quotes
  std::shared_ptr<const std::string> file;
  int line = 0;
  [[noreturn]] void fail(const std::string& msg) const { throw SceneError(file ? *file : "?", line, msg); }
};

// A stack of files: Include pushes one, reaching the end of it pops back to the includer.
class Tokenizer {
 public:
  // Throws SceneError(from_file, from_line) if the file cannot be read.
  void push_file(const std::string& path, const std::string& from_file, int from_line);
  Token next();
  const Token& peek();
  const std::string& current_file() const;
  // Every file pushed so far (the scene and what it includes), in order.
  const std::vector<std::string>& files() const { return files_; }

 private:
  struct Source {
    std::shared_ptr<const std::string> file;
    std::string text;
    size_t pos = 0;
    int line = 1;
  };
  Token scan();
  std::vector<Source> stack_;
  std::optional<Token> peeked_;
  std::shared_ptr<const std::string> last_file_;
  int last_line_ = 0;
  std::vector<std::string> files_;
};

// One "type name" [values] entry.
struct Param {
  std::string type, name;
  std::vector<double> nums;
  std::vector<std::string> strs;
  std::shared_ptr<const std::string> file;
  int line = 0;
  mutable bool used = false;
  [[noreturn]] void fail(const std::string& msg) const {
    throw SceneError(file ? *file : "?", line, "parameter \"" + type + " " + name + "\": " + msg);
  }
};

class ParamList {
 public:
  std::vector<Param> params;

  const Param* find(const std::string& name) const;
  // Typed getters: throw SceneError if the parameter exists with another type or a bad count.
  float get_float(const std::string& name, float def) const;
  int get_int(const std::string& name, int def) const;
  bool get_bool(const std::string& name, bool def) const;
  std::string get_string(const std::string& name, const std::string& def) const;
  std::optional<std::string> get_texture(const std::string& name) const;
  std::vector<float> get_floats(const std::string& name) const;
  std::vector<int> get_ints(const std::string& name) const;
  std::vector<Vec3> get_point3s(const std::string& name) const;  // point3 / point
  std::vector<Vec3> get_normals(const std::string& name) const;  // normal / normal3
  std::vector<Vec2> get_point2s(const std::string& name) const;  // point2 (also float pairs)
  Vec3 get_point3(const std::string& name, Vec3 def) const;
  // rgb / spectrum (single float, named metal spectra) / blackbody -> RGB. `illuminant`: blackbody
  // allowed (normalized to luminance 1, as pbrt-v4 normalizes lights by SpectrumToPhotometric).
  std::optional<Rgb> get_rgb(const std::string& name, bool illuminant) const;
  // If the parameter is present, every number in it must lie in [lo, hi] ((lo, hi] with lo_open);
  // otherwise throws SceneError naming file:line, the parameter and the range. Does not mark it used.
  void check_range(const std::string& name, double lo, double hi = HUGE_VAL, bool lo_open = false) const;
  // Marks a parameter as read without interpreting it.
  void ignore(const std::string& name) const;
  // Throws for the first parameter nobody read (pbrt-v4: "unused parameter").
  void check_unused(const std::string& context) const;
  // Names of unread parameters (for warnings).
  std::vector<std::string> unused() const;

 private:
  // The names the reader asked for (find, the getters, check_range), in order: what a parameter
  // nobody read was probably meant to be ("did you mean").
  mutable std::vector<std::string> asked_;
};

// Reads "type name" value... entries while the next token is a quoted string.
ParamList parse_params(Tokenizer& tok);

// CIE 1931 blackbody colour in linear sRGB, normalized to luminance Y = 1 (negatives clamped).
Rgb blackbody_rgb(float kelvin);
// RGB approximations of pbrt-v4's named metal spectra ("metal-Au-eta", ...); nullopt if unknown.
std::optional<Rgb> named_spectrum_rgb(const std::string& name);
// Index of refraction at the d line for pbrt-v4's named glasses ("glass-BK7", ...).
std::optional<float> named_glass_ior(const std::string& name);

// Shortest text that reads back as v (2000000000, not 2e+09).
std::string format_number(double v);

// Prints "FILE:LINE: warning: msg" to stderr.
void warn(const Token& at, const std::string& msg);

// Texture names -> indices into Scene::textures (pbrt keeps spectrum and float textures apart).
struct NamedTextures {
  std::map<std::string, int> spectrum, floats;
};

// pbrt-v4 "diffuse", "conductor", "dielectric", "coateddiffuse" (pbrt_materials.cpp). Errors name d's file:line.
Material make_material(const Token& d, const std::string& type, const std::string& name, const ParamList& pl,
                       const NamedTextures& nt, const std::vector<Texture>& textures);
// Texture classes imagemap, checkerboard, constant, scale. `resolve` maps a file name in the
// scene to a path.
Texture make_texture(const Token& d, const std::string& name, const std::string& cls, const ParamList& pl,
                     const NamedTextures& nt, const std::vector<Texture>& textures,
                     const std::function<std::string(const std::string&)>& resolve);

}  // namespace rl::pbrt
