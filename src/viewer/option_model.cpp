#include "viewer/option_model.h"

#include <cmath>
#include <type_traits>

#include "frame/integrator.h"

namespace rl::viewer {

namespace {

// A slider is usable when a drag across it spans the range in steps a user can hit; wider
// ranges (spp up to 2^20, resolution up to 16384) get a drag widget clamped to the range.
constexpr double kSliderSpan = 1024;

struct WidgetBuilder {
  std::vector<OptionWidget> out;
  template <class T>
  void operator()(const char* key, T&, const char* help, Range r = {}) {
    OptionWidget w;
    w.key = key;
    w.help = help;
    const std::string k = key;
    const size_t dot = k.find('.');
    w.group = dot == std::string::npos ? "general" : k.substr(0, dot);
    if constexpr (std::is_same_v<T, bool>) {
      w.kind = WidgetKind::checkbox;
    } else if constexpr (NamedEnum<T>) {
      w.kind = WidgetKind::combo;
      for (const auto& [v, n] : EnumNames<T>::values) w.choices.emplace_back(n);
    } else if constexpr (std::is_same_v<T, uint64_t>) {
      w.kind = WidgetKind::seed;
    } else if constexpr (std::is_same_v<T, int> || std::is_same_v<T, float>) {
      w.is_float = std::is_same_v<T, float>;
      w.lo = r.lo;
      w.hi = r.hi;
      const bool bounded = std::isfinite(r.lo) && std::isfinite(r.hi);
      w.kind = bounded && r.hi - r.lo <= kSliderSpan ? WidgetKind::slider : WidgetKind::drag;
    } else if (k == "integrator") {
      w.kind = WidgetKind::combo;
      for (const auto& i : integrator_registry()) w.choices.emplace_back(i.name);
    } else {
      w.kind = WidgetKind::text;
    }
    out.push_back(std::move(w));
  }
};

}  // namespace

const std::vector<OptionWidget>& option_widgets() {
  static const std::vector<OptionWidget> widgets = [] {
    Options o;
    WidgetBuilder b;
    visit_options(o, b);
    return std::move(b.out);
  }();
  return widgets;
}

const OptionWidget* find_widget(std::string_view key) {
  for (const auto& w : option_widgets())
    if (w.key == key) return &w;
  return nullptr;
}

Effect option_effect(std::string_view key) {
  if (key.starts_with("output.")) return Effect::display;
  if (key == "render.threads") return Effect::threads;
  return Effect::restart;
}

Effect apply_option(Options& o, const std::string& key, const std::string& value) {
  Options next = o;
  set_option(next, key, value);
  // The panel shows every group's options as widgets (no key to mistype) and switches integrators
  // with the others' settings kept: its edits are not checked against the integrator's groups, and
  // the command line's keys were checked when the viewer started.
  next.explicit_keys.clear();
  validate_options(next);
  find_integrator(next.integrator);
  o = std::move(next);
  return option_effect(key);
}

std::string option_value(const Options& o, std::string_view key) {
  for (const auto& [k, v] : option_values(o))
    if (k == key) return v;
  throw OptionError("unknown option '" + std::string(key) + "'");
}

}  // namespace rl::viewer
