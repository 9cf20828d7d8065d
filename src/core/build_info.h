#pragma once

namespace rl {

// The renderer's identity: "VERSION+src.HASH", where HASH covers every source file of the build
// (cmake/build_id.cmake, regenerated at each build). Anything cached across runs (study rows,
// reference images) keys on it, so results of an older binary are never reused as current.
const char* build_id();

}  // namespace rl
