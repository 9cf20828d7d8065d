#include "core/option_io.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <cstdio>

namespace rl {

namespace {
[[noreturn]] void bad(std::string_view key, std::string_view text, const char* what) {
  throw OptionError("option '" + std::string(key) + "': '" + std::string(text) + "' is not " + what);
}
}  // namespace

std::string format_value(bool v) { return v ? "true" : "false"; }
std::string format_value(int v) { return std::to_string(v); }
std::string format_value(uint64_t v) { return std::to_string(v); }
std::string format_value(float v) {
  // Shortest text that round-trips, so echoed configs reproduce the run exactly.
  char buf[64];
  auto res = std::to_chars(buf, buf + sizeof(buf), v);
  return std::string(buf, res.ptr);
}
std::string format_value(const std::string& v) { return v; }

void parse_value(std::string_view key, std::string_view text, bool& out) {
  if (text == "true" || text == "1" || text == "on" || text == "yes") out = true;
  else if (text == "false" || text == "0" || text == "off" || text == "no") out = false;
  else bad(key, text, "a boolean (true|false)");
}

void parse_value(std::string_view key, std::string_view text, int& out) {
  int v = 0;
  auto res = std::from_chars(text.data(), text.data() + text.size(), v);
  if (res.ec != std::errc() || res.ptr != text.data() + text.size()) bad(key, text, "an integer");
  out = v;
}

void parse_value(std::string_view key, std::string_view text, uint64_t& out) {
  uint64_t v = 0;
  auto res = std::from_chars(text.data(), text.data() + text.size(), v);
  if (res.ec != std::errc() || res.ptr != text.data() + text.size()) bad(key, text, "a non-negative integer");
  out = v;
}

void parse_value(std::string_view key, std::string_view text, float& out) {
  float v = 0;
  auto res = std::from_chars(text.data(), text.data() + text.size(), v);
  if (res.ec != std::errc() || res.ptr != text.data() + text.size() || !std::isfinite(v)) bad(key, text, "a finite number");
  out = v;
}

void parse_value(std::string_view, std::string_view text, std::string& out) { out = std::string(text); }

void check_range(std::string_view key, double v, Range r) {
  if (!(v >= r.lo && v <= r.hi)) {  // NaN is out of every range
    // Shortest round-trip text: 2000000000, not 2e+09; an open end reads "inf".
    auto num = [](double d) { return std::isinf(d) ? std::string(d > 0 ? "inf" : "-inf") : fmt::format("{}", d); };
    throw OptionError("option '" + std::string(key) + "': value " + num(v) + " is out of range [" + num(r.lo) + ", " +
                      num(r.hi) + "]");
  }
}

}  // namespace rl
