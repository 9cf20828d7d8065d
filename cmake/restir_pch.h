// The precompiled header of every restir-lab target (CMake option RESTIR_PCH; CMakeLists.txt's
// restir_pch()): the standard library, fmt and nlohmann-json, the headers most files include and
// whose parsing was a third of their compile time. Only third-party and standard headers: the
// project's own headers stay out, so that editing one rebuilds only the files that include it.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <span>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
