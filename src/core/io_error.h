// The error type of the file system edge: a lock file, an output path or an output file that
// cannot be opened, created or written (image files have their own, image/image_io.h's ImageError).
#pragma once
#include <stdexcept>

namespace rl {

// A file or folder that cannot be opened, locked, created or written; what() names the path.
struct IoError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace rl
