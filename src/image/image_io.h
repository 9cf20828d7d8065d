// Image files: OpenEXR (read any scanline/tiled single-part layout, write float RGB + metadata),
// PNG/JPEG/HDR through stb_image, PNG out through stb_image_write. Every write is atomic.
//
// Errors: every function throws ImageError with one line that starts with the function name and
// names the file, e.g.
//   "read_image: 'scenes/x.exr': no such file"
//   "read_image: 'a.exr': malformed or truncated OpenEXR file: <OpenEXR's reason>"
#pragma once
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "image/image.h"

namespace rl {

// An image file that cannot be read or written.
struct ImageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Reads an image into linear RGB floats, row 0 at the top. Dispatch on the (case-insensitive)
// extension:
//  .exr  single-part scanline or tiled file, half/float/uint channels, any compression OpenEXR
//        3.1 supports (incl. DWAA/DWAB). Channels: R,G,B if present (a missing one of the three
//        reads as 0); else luminance/chroma Y,RY,BY (converted by OpenEXR's RgbaInputFile); else
//        Y alone (grey). Other channels (A, depth, AOVs) are ignored. The image is the data
//        window; pixel (0,0) is the data window's min corner. Values are returned as stored:
//        lossy DWAA/DWAB files can hold small negative values from DCT ringing (the shared env
//        maps have ~0.2% such pixels, min ~ -0.003); consumers needing >= 0 must clamp.
//  .png/.jpg/.jpeg/.bmp/.tga  via stb_image, 8 or 16 bit, decoded from sRGB to linear
//        (IEC 61966-2-1); grey is replicated to RGB; alpha is dropped (not premultiplied).
//  .hdr  Radiance RGBE via stb_image, linear as stored.
// Anything else: ImageError naming the extension.
Image read_image(const std::string& path);

// Writes linear float RGB (32-bit float channels R,G,B, ZIP compression: lossless), with the
// given string attributes in the header (e.g. "restir.config" -> JSON text, "restir.version").
// Attribute names must be non-empty and must not collide with OpenEXR's standard attributes
// (channels, compression, dataWindow, displayWindow, lineOrder, pixelAspectRatio,
// screenWindowCenter, screenWindowWidth, ...).
// Atomic: writes "<path>.tmp-<pid>" in the same directory, then rename()s it over path; on any
// failure the temp file is removed, path is left untouched, and ImageError is thrown.
// (The temp name is per process: two threads of one process must not write the same path.)
void write_exr(const std::string& path, const Image& img,
               const std::vector<std::pair<std::string, std::string>>& metadata = {});

// Writes named 32-bit float channels (each width x height values, row-major), e.g. AOV layers
// "Albedo.R", "N.X", "Z": one multi-channel EXR as pbrt-v4 and Mitsuba write them. Metadata,
// compression and atomicity as write_exr.
void write_exr_channels(const std::string& path, int width, int height,
                        const std::vector<std::pair<std::string, std::vector<float>>>& channels,
                        const std::vector<std::pair<std::string, std::string>>& metadata = {});

// The string attributes of an EXR header, in the header's (alphabetical) order. Attributes of
// other types are skipped.
std::vector<std::pair<std::string, std::string>> read_exr_metadata(const std::string& path);

// 8-bit RGB PNG. Expects display-ready values (already tone mapped and sRGB-encoded, see
// tonemap()); each channel is clamped to [0,1] (NaN -> 0) and quantized as round(255 v). Atomic.
void write_png(const std::string& path, const Image& ldr_srgb_0_1);

// Writes text (JSON sidecar, CSV) atomically, same temp-and-rename protocol as write_exr.
void write_text_file_atomic(const std::string& path, const std::string& text);

}  // namespace rl
