// Generic machinery behind the options: each options struct is listed once in a `visit` function
// (see render/options.h); the visitors here turn that one list into parsing (CLI --set key=value,
// JSON), printing (config echo, EXR header, CSV columns) and --help. Keys are dotted paths.
#pragma once
#include <array>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace rl {

// Thrown for unknown keys, unparsable or out-of-range values; the CLI prints it as one line.
struct OptionError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Allowed numeric range of a field (inclusive).
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
};

// Specialize for every enum used as an option: a static `values` array of {enum, name} pairs.
template <class E>
struct EnumNames;

template <class E>
concept NamedEnum = std::is_enum_v<E> && requires { EnumNames<E>::values; };

template <NamedEnum E>
std::string_view enum_name(E e) {
  for (const auto& [v, n] : EnumNames<E>::values)
    if (v == e) return n;
  return "?";
}

template <NamedEnum E>
std::string enum_choices() {
  std::string s;
  for (const auto& [v, n] : EnumNames<E>::values) {
    if (!s.empty()) s += '|';
    s += n;
  }
  return s;
}

// String conversions for option values. parse_* throw OptionError with a message that names the key.
std::string format_value(bool v);
std::string format_value(int v);
std::string format_value(uint64_t v);
std::string format_value(float v);
std::string format_value(const std::string& v);
template <NamedEnum E>
std::string format_value(E v) { return std::string(enum_name(v)); }

void parse_value(std::string_view key, std::string_view text, bool& out);
void parse_value(std::string_view key, std::string_view text, int& out);
void parse_value(std::string_view key, std::string_view text, uint64_t& out);
void parse_value(std::string_view key, std::string_view text, float& out);
void parse_value(std::string_view key, std::string_view text, std::string& out);
template <NamedEnum E>
void parse_value(std::string_view key, std::string_view text, E& out) {
  for (const auto& [v, n] : EnumNames<E>::values)
    if (text == n) {
      out = v;
      return;
    }
  throw OptionError("option '" + std::string(key) + "': '" + std::string(text) + "' is not one of " + enum_choices<E>());
}

template <class T>
const char* type_name() {
  if constexpr (std::is_same_v<T, bool>) return "bool";
  else if constexpr (std::is_same_v<T, int>) return "int";
  else if constexpr (std::is_same_v<T, uint64_t>) return "uint";
  else if constexpr (std::is_same_v<T, float>) return "float";
  else if constexpr (std::is_same_v<T, std::string>) return "string";
  else return "choice";
}

void check_range(std::string_view key, double v, Range r);

// Visitor: set one key from text. `found` tells whether the key exists.
struct OptionSetter {
  std::string_view key, text;
  bool found = false;
  template <class T>
  void operator()(const char* k, T& field, const char*, Range r = {}) {
    if (found || key != k) return;
    found = true;
    T v = field;
    parse_value(key, text, v);
    if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) check_range(key, double(v), r);
    field = v;
  }
};

// Visitor: collect key/value text pairs in declaration order.
struct OptionPrinter {
  std::vector<std::pair<std::string, std::string>> out;
  template <class T>
  void operator()(const char* k, T& field, const char*, Range = {}) {
    out.emplace_back(k, format_value(field));
  }
};

// Visitor: collect help lines (key, type or choices, default, description).
struct OptionHelp {
  struct Line {
    std::string key, type, default_value, help;
  };
  std::vector<Line> lines;
  template <class T>
  void operator()(const char* k, T& field, const char* help, Range r = {}) {
    std::string type;
    if constexpr (NamedEnum<T>) type = enum_choices<T>();
    else type = type_name<T>();
    std::string h = help;
    if (r.lo != -std::numeric_limits<double>::infinity() || r.hi != std::numeric_limits<double>::infinity()) {
      h += " [" + format_value(float(r.lo)) + ", " +
           (r.hi == std::numeric_limits<double>::infinity() ? std::string("inf") : format_value(float(r.hi))) + "]";
    }
    lines.push_back({k, type, format_value(field), h});
  }
};

}  // namespace rl
