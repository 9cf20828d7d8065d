// Output safety for the command line: every output path of a command is checked before any work
// starts, so that a run never destroys a user's file and never fails at the end for a reason known
// at the start. Errors are IoError (core/io_error.h) with one line naming the flag and the path.
#pragma once
#include <string>
#include <vector>

#include "core/io_error.h"

namespace rl {

struct OutputFile {
  std::string path;
  std::string flag;                     // how the user gave it ("-o", "--png", "sidecar of -o")
  std::vector<std::string> extensions;  // allowed lower-case extensions (".exr"); empty: any
  bool directory = false;               // a folder to create (--frame-dir), not a file
  bool sidecar = false;                 // may only replace a sidecar of ours (replaceable_sidecar)
};

// Refuses, in this order: an output that is one of the inputs (scene, config, included files,
// meshes, textures); two outputs that are the same file; an extension that contradicts the
// format; an output that is an existing directory (or, for `directory`, an existing file); a
// sidecar that would replace a file that is not a sidecar of ours. Then
// creates every missing output folder and checks that each is writable. Throws IoError.
void check_outputs(const std::vector<OutputFile>& outputs, const std::vector<std::string>& inputs);

// True when a and b name the same file (existing: same inode; else the same normalized path).
bool same_file(const std::string& a, const std::string& b);

// The JSON sidecar marker: a sidecar written by `restir render` has this key at the top level.
inline constexpr const char* kSidecarMarker = "restir_sidecar";

// True when path does not exist, or is a JSON sidecar of ours (the marker key, or the exact key
// set of the sidecars of earlier versions): only such a file may be replaced by a new sidecar.
bool replaceable_sidecar(const std::string& path);

}  // namespace rl
