// The viewer's option panel as data: one widget per option of visit_options (the one list), with
// its kind, range and choices, and what a change of it invalidates. The GUI draws these widgets;
// nothing here knows ImGui, so the model is unit-tested without a display.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "frame/options.h"

namespace rl::viewer {

enum class WidgetKind {
  checkbox,  // bool
  combo,     // enum, and the integrator name (choices from the registry)
  slider,    // int or float with a documented range narrow enough to drag across
  drag,      // int or float with a wide or open range (clamped to it)
  seed,      // uint64 (render.seed)
  text,      // string (render.camera_path), applied on Enter
};

// What a change invalidates.
enum class Effect {
  display,  // output.*: only the display transform; the frames are not re-rendered
  threads,  // render.threads: the worker thread count (the image does not depend on it)
  restart,  // anything else: a new integrator (no history) and a reset accumulation
};

struct OptionWidget {
  std::string key, help;
  std::string group;  // the key's prefix ("film", "di", ...; "general" for "integrator")
  WidgetKind kind = WidgetKind::text;
  bool is_float = false;             // slider / drag: float field (else int)
  double lo = 0, hi = 0;             // slider / drag: the documented Range
  std::vector<std::string> choices;  // combo
};

// Every option in declaration order (the order of `restir options`).
const std::vector<OptionWidget>& option_widgets();
// The widget of a key, or null for an unknown key.
const OptionWidget* find_widget(std::string_view key);
// What changing `key` invalidates.
Effect option_effect(std::string_view key);

// Applies key=value to `o` if the result is valid (set_option, then validate_options and the
// integrator name); otherwise leaves `o` unchanged and throws OptionError. Returns the effect.
Effect apply_option(Options& o, const std::string& key, const std::string& value);

// The current value of one option as text (as `restir options` prints it).
std::string option_value(const Options& o, std::string_view key);

}  // namespace rl::viewer
