// The display transform's settings (output.* options): tone mapper, exposure, white point, sRGB.
// Its own small header so that image/tonemap.h does not depend on the integrators' option list.
#pragma once
#include <array>
#include <utility>

#include "core/option_io.h"

namespace rl {

enum class Tonemap { linear, reinhard, modified_reinhard, aces };

template <> struct EnumNames<Tonemap> {
  static constexpr std::array<std::pair<Tonemap, const char*>, 4> values{{{Tonemap::linear, "linear"},
      {Tonemap::reinhard, "reinhard"}, {Tonemap::modified_reinhard, "modified-reinhard"}, {Tonemap::aces, "aces"}}};
};

struct OutputOptions {
  Tonemap tonemap = Tonemap::aces;
  float exposure = 0;
  float white_point = 4;
  bool srgb = true;
};

}  // namespace rl
