// How a light is picked for next-event estimation: by emitted power (alias table) or uniformly.
// Its own small header so that scene/lights.h does not depend on the integrators' option list.
#pragma once
#include <array>
#include <utility>

#include "core/option_io.h"

namespace rl {

enum class LightSelection { power, uniform };

template <> struct EnumNames<LightSelection> {
  static constexpr std::array<std::pair<LightSelection, const char*>, 2> values{
      {{LightSelection::power, "power"}, {LightSelection::uniform, "uniform"}}};
};

}  // namespace rl
