#include "viewer/script.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rl::viewer {

bool parse_int(const std::string& word, int& out) {
  auto r = std::from_chars(word.data(), word.data() + word.size(), out);
  return r.ec == std::errc() && r.ptr == word.data() + word.size();
}

bool parse_float(const std::string& word, float& out) {
  auto r = std::from_chars(word.data(), word.data() + word.size(), out);
  return r.ec == std::errc() && r.ptr == word.data() + word.size() && std::isfinite(out);
}

namespace {

std::vector<std::string> split_words(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

std::string trim(const std::string& s) {
  size_t a = s.find_first_not_of(" \t\r"), b = s.find_last_not_of(" \t\r");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

// Checks the argument count and form of one command; `fail` throws with the line's location.
template <class Fail>
void check_command(const ScriptCommand& c, Fail fail) {
  const auto n = c.args.size();
  auto count = [&](size_t want, const char* form) {
    if (n != want) fail(c.verb + ": expected " + form);
  };
  int i = 0;
  float f = 0;
  if (c.verb == "set") {
    if (n != 2 || c.args[1].empty()) fail("set: expected 'set KEY VALUE'");
  } else if (c.verb == "frames") {
    count(1, "'frames N'");
    if (!parse_int(c.args[0], i) || i < 1 || i > 1000000) fail("frames: '" + c.args[0] + "' is not an integer in [1, 1000000]");
  } else if (c.verb == "screenshot" || c.verb == "save-config") {
    count(1, ("'" + c.verb + " PATH'").c_str());
  } else if (c.verb == "view") {
    count(1, "'view radiance|error|split'");
    if (c.args[0] != "radiance" && c.args[0] != "error" && c.args[0] != "split")
      fail("view: '" + c.args[0] + "' is not one of radiance|error|split");
  } else if (c.verb == "split") {
    count(1, "'split F' with F in [0, 1]");
    if (!parse_float(c.args[0], f) || f < 0 || f > 1) fail("split: '" + c.args[0] + "' is not a number in [0, 1]");
  } else if (c.verb == "accumulate") {
    count(1, "'accumulate on|off'");
    if (c.args[0] != "on" && c.args[0] != "off") fail("accumulate: '" + c.args[0] + "' is not on|off");
  } else if (c.verb == "scale") {
    count(1, "'scale 1|0.5|0.25'");
    if (c.args[0] != "1" && c.args[0] != "0.5" && c.args[0] != "0.25") fail("scale: '" + c.args[0] + "' is not one of 1|0.5|0.25");
  } else if (c.verb == "camera") {
    const std::string sub = n ? c.args[0] : "";
    size_t want = sub == "orbit" ? 3 : sub == "move" ? 4 : sub == "reset" ? 1 : sub == "mode" ? 2 : 0;
    if (want == 0) fail("camera: expected 'camera orbit DYAW DPITCH', 'camera move DX DY DZ', 'camera reset' or 'camera mode orbit|fly'");
    if (n != want) fail("camera " + sub + ": wrong number of arguments");
    if (sub == "mode" && c.args[1] != "orbit" && c.args[1] != "fly") fail("camera mode: '" + c.args[1] + "' is not orbit|fly");
    if (sub == "orbit" || sub == "move")
      for (size_t k = 1; k < n; ++k)
        if (!parse_float(c.args[k], f)) fail("camera " + sub + ": '" + c.args[k] + "' is not a number");
  } else if (c.verb == "record") {
    const std::string sub = n ? c.args[0] : "";
    if (!((sub == "start" || sub == "stop") && n == 1) && !(sub == "save" && n == 2))
      fail("record: expected 'record start', 'record stop' or 'record save PATH'");
  } else if (c.verb == "reference") {
    const std::string sub = n ? c.args[0] : "";
    if (!((sub == "off" || sub == "wait") && n == 1) && !(sub == "on" && (n == 1 || n == 2)))
      fail("reference: expected 'reference on [SPP]', 'reference off' or 'reference wait'");
    if (sub == "on" && n == 2 && (!parse_int(c.args[1], i) || i < 1 || i > (1 << 24)))
      fail("reference on: '" + c.args[1] + "' is not a sample count in [1, 16777216]");
  } else if (c.verb == "quit") {
    count(0, "no arguments");
  } else {
    fail("unknown command '" + c.verb +
         "' (commands: set, frames, screenshot, view, split, accumulate, scale, camera, record, reference, save-config, quit)");
  }
}

}  // namespace

Script parse_script(const std::string& text, const std::string& path) {
  Script script;
  script.path = path;
  std::istringstream in(text);
  std::string raw;
  for (int line = 1; std::getline(in, raw); ++line) {
    std::string s = raw.substr(0, raw.find('#'));
    s = trim(s);
    if (s.empty()) continue;
    ScriptCommand c;
    c.line = line;
    const size_t sp = s.find_first_of(" \t");
    c.verb = s.substr(0, sp);
    const std::string rest = sp == std::string::npos ? "" : trim(s.substr(sp));
    if (c.verb == "set") {
      // The value is the rest of the line: a camera path file name may hold spaces.
      const size_t k = rest.find_first_of(" \t");
      c.args = {rest.substr(0, k), k == std::string::npos ? "" : trim(rest.substr(k))};
      if (c.args[0].empty()) c.args.clear();
    } else if (c.verb == "screenshot" || c.verb == "save-config") {
      if (!rest.empty()) c.args = {rest};
    } else {
      c.args = split_words(rest);
    }
    check_command(c, [&](const std::string& msg) { throw ScriptError(path + ":" + std::to_string(line) + ": " + msg); });
    script.commands.push_back(std::move(c));
  }
  return script;
}

Script load_script(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ScriptError("--script '" + path + "': cannot open the file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_script(ss.str(), path);
}

}  // namespace rl::viewer
