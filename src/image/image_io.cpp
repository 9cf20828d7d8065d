// Image file I/O: OpenEXR through the C++ API of OpenEXR 3.1, LDR/HDR through stb. See image_io.h.
#include "image/image_io.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <stdexcept>

#include <OpenEXR/ImfArray.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfRgbaFile.h>
#include <OpenEXR/ImfStdIO.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <fmt/format.h>
#include <stb_image.h>
#include <stb_image_write.h>

#include "image/tonemap.h"

namespace rl {

namespace fs = std::filesystem;

namespace {

// Larger images are rejected as malformed headers rather than attempted (2^28 pixels = 3 GiB).
constexpr int64_t kMaxPixels = int64_t(1) << 28;

[[noreturn]] void fail(const char* fn, const std::string& path, const std::string& why) {
  throw ImageError(fmt::format("{}: '{}': {}", fn, path, why));
}

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

// A readable regular file, or one clear line saying why not.
void check_readable(const char* fn, const std::string& path) {
  std::error_code ec;
  fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) fail(fn, path, "no such file");
  if (fs::is_directory(st)) fail(fn, path, "is a directory, not an image file");
  std::ifstream probe(path, std::ios::binary);
  if (!probe) fail(fn, path, fmt::format("cannot open for reading: {}", std::strerror(errno)));
}

void check_image_shape(const char* fn, const std::string& path, const Image& img) {
  if (img.width <= 0 || img.height <= 0)
    fail(fn, path, fmt::format("cannot write an empty image ({}x{})", img.width, img.height));
  if (img.pixels.size() != size_t(img.width) * size_t(img.height))
    fail(fn, path, fmt::format("image has {} pixels but is {}x{}", img.pixels.size(), img.width, img.height));
}

// fsync the finished temp file so the rename never publishes an empty or partial file after a
// crash (rename is atomic for the name, not for the data).
void sync_file(const std::string& path) {
  int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0) throw ImageError(fmt::format("cannot reopen temp file to sync: {}", std::strerror(errno)));
  int r = ::fsync(fd);
  int err = errno;
  ::close(fd);
  if (r != 0) throw ImageError(fmt::format("fsync failed: {}", std::strerror(err)));
}

// The atomic-write protocol of every writer: write(tmp) -> fsync -> rename(tmp, path). On failure
// the temp file (only if it is ours: a regular file) is removed and path is left untouched.
void atomic_write(const char* fn, const std::string& path, const std::function<void(const std::string&)>& write) {
  // No early "target is a directory" check on purpose: rename() refuses that (EISDIR), which
  // runs the same cleanup path as every other failure.
  std::error_code ec;
  const std::string tmp = path + ".tmp-" + std::to_string(::getpid());
  if (fs::exists(fs::symlink_status(tmp, ec)) && !fs::is_regular_file(fs::symlink_status(tmp, ec)))
    fail(fn, path, fmt::format("temp path '{}' exists and is not a regular file", tmp));
  try {
    write(tmp);
    sync_file(tmp);
    fs::rename(tmp, path);  // POSIX rename(): atomic replacement within one file system
  } catch (const std::exception& e) {
    std::error_code ignored;
    if (fs::is_regular_file(fs::symlink_status(tmp, ignored))) fs::remove(tmp, ignored);
    fail(fn, path, e.what());
  }
}

// ---------------------------------------------------------------------------------------------
// OpenEXR

Image read_exr(const std::string& path) {
  const char* fn = "read_image";
  try {
    Imf::InputFile file(path.c_str());
    const Imf::Header& header = file.header();
    const Imath::Box2i dw = header.dataWindow();
    const int64_t w = int64_t(dw.max.x) - dw.min.x + 1, h = int64_t(dw.max.y) - dw.min.y + 1;
    if (w <= 0 || h <= 0 || w * h > kMaxPixels)
      fail(fn, path, fmt::format("implausible data window {}x{}", w, h));
    const Imf::ChannelList& channels = header.channels();
    auto has = [&](const char* name) { return channels.findChannel(name) != nullptr; };

    Image img{int(w), int(h)};
    if (has("R") || has("G") || has("B") || (has("Y") && !has("RY") && !has("BY"))) {
      // Generic path: float slices straight into Image::pixels (exact for float data, converts
      // half and uint). A missing R/G/B channel is filled with 0 by OpenEXR (Slice fillValue).
      const bool grey = !(has("R") || has("G") || has("B"));
      const char* names[3] = {"R", "G", "B"};
      for (const char* name : names)
        if (const Imf::Channel* c = channels.findChannel(grey ? "Y" : name); c && (c->xSampling != 1 || c->ySampling != 1))
          fail(fn, path, fmt::format("subsampled channel {} is not supported", grey ? "Y" : name));
      Imf::FrameBuffer fb;
      char* base = reinterpret_cast<char*>(img.pixels.data());
      for (int c = 0; c < (grey ? 1 : 3); ++c)
        fb.insert(grey ? "Y" : names[c], Imf::Slice::Make(Imf::FLOAT, base + c * sizeof(float), dw, sizeof(Rgb),
                                                          sizeof(Rgb) * size_t(w)));
      file.setFrameBuffer(fb);
      file.readPixels(dw.min.y, dw.max.y);
      if (grey)
        for (Rgb& p : img.pixels) p = Rgb(p.x);
      return img;
    }
    if (has("Y")) {
      // Luminance/chroma (Y, RY, BY; chroma usually subsampled): RgbaInputFile converts to RGB.
      Imf::RgbaInputFile rgba(path.c_str());
      Imf::Array2D<Imf::Rgba> buf(h, w);
      rgba.setFrameBuffer(&buf[0][0] - dw.min.x - int64_t(dw.min.y) * w, 1, size_t(w));
      rgba.readPixels(dw.min.y, dw.max.y);
      for (int64_t y = 0; y < h; ++y)
        for (int64_t x = 0; x < w; ++x) {
          const Imf::Rgba& p = buf[y][x];
          img.pixels[size_t(y * w + x)] = Rgb(float(p.r), float(p.g), float(p.b));
        }
      return img;
    }
    std::string names;
    for (auto it = channels.begin(); it != channels.end(); ++it) names += std::string(names.empty() ? "" : ",") + it.name();
    fail(fn, path, fmt::format("no R,G,B or Y channels (channels: {})", names.empty() ? "none" : names));
  } catch (const ImageError&) {
    throw;  // already one of ours
  } catch (const std::exception& e) {  // OpenEXR's (Iex) and the standard library's
    fail(fn, path, fmt::format("malformed or truncated OpenEXR file: {}", e.what()));
  }
}

// ---------------------------------------------------------------------------------------------
// stb (PNG, JPEG, BMP, TGA, HDR)

struct StbFree {
  void operator()(void* p) const { stbi_image_free(p); }
};

std::string stb_reason() {
  const char* r = stbi_failure_reason();
  return r ? r : "unknown error";
}

// sRGB 8-bit -> linear, IEC 61966-2-1 decode, tabulated once.
const std::array<float, 256>& srgb8_to_linear() {
  static const std::array<float, 256> lut = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[size_t(i)] = srgb_decode(float(i) / 255.0f);
    return t;
  }();
  return lut;
}

Image read_stb(const std::string& path, const std::string& ext) {
  const char* fn = "read_image";
  int w = 0, h = 0, n = 0;
  if (ext == ".hdr") {
    if (!stbi_is_hdr(path.c_str())) fail(fn, path, "not a Radiance HDR (RGBE) file");
    std::unique_ptr<float, StbFree> data(stbi_loadf(path.c_str(), &w, &h, &n, 3));
    if (!data) fail(fn, path, "malformed Radiance HDR file: " + stb_reason());
    Image img(w, h);
    const float* d = data.get();
    for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = Rgb(d[3 * i], d[3 * i + 1], d[3 * i + 2]);
    return img;
  }
  if (stbi_is_16_bit(path.c_str())) {
    std::unique_ptr<uint16_t, StbFree> data(stbi_load_16(path.c_str(), &w, &h, &n, 3));
    if (!data) fail(fn, path, "malformed image file: " + stb_reason());
    Image img(w, h);
    const uint16_t* d = data.get();
    for (size_t i = 0; i < img.pixels.size(); ++i)
      img.pixels[i] = Rgb(srgb_decode(d[3 * i] / 65535.0f), srgb_decode(d[3 * i + 1] / 65535.0f),
                          srgb_decode(d[3 * i + 2] / 65535.0f));
    return img;
  }
  std::unique_ptr<unsigned char, StbFree> data(stbi_load(path.c_str(), &w, &h, &n, 3));
  if (!data) fail(fn, path, "malformed image file: " + stb_reason());
  Image img(w, h);
  const unsigned char* d = data.get();
  const auto& lut = srgb8_to_linear();
  for (size_t i = 0; i < img.pixels.size(); ++i)
    img.pixels[i] = Rgb(lut[d[3 * i]], lut[d[3 * i + 1]], lut[d[3 * i + 2]]);
  return img;
}

}  // namespace

Image read_image(const std::string& path) {
  check_readable("read_image", path);
  const std::string ext = lower_extension(path);
  if (ext == ".exr") return read_exr(path);
  if (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp" || ext == ".tga" || ext == ".hdr")
    return read_stb(path, ext);
  fail("read_image", path,
       fmt::format("unsupported extension '{}' (supported: .exr .png .jpg .jpeg .bmp .tga .hdr)", ext));
}

namespace {
// One slice per channel: (name, base pointer, x stride in bytes); y stride = width x-strides.
struct ExrSlice {
  std::string name;
  const float* base;
  size_t x_stride;
};
void write_exr_slices(const char* fn, const std::string& path, int width, int height, const std::vector<ExrSlice>& slices,
                      const std::vector<std::pair<std::string, std::string>>& metadata) {
  Imf::Header header(width, height);
  header.compression() = Imf::ZIP_COMPRESSION;  // lossless
  for (const ExrSlice& s : slices) {
    if (s.name.empty() || header.channels().findChannel(s.name)) fail(fn, path, fmt::format("channel name '{}' is empty or duplicated", s.name));
    header.channels().insert(s.name, Imf::Channel(Imf::FLOAT));
  }
  for (const auto& [name, value] : metadata) {
    if (name.empty()) fail(fn, path, "metadata attribute with an empty name");
    if (header.find(name) != header.end())
      fail(fn, path, fmt::format("metadata attribute '{}' is duplicated or collides with a standard EXR attribute", name));
    header.insert(name, Imf::StringAttribute(value));
  }
  atomic_write(fn, path, [&](const std::string& tmp) {
    // Our own stream so that a failed flush (disk full) is seen: OutputFile's destructor, which
    // writes the line offset table, swallows errors.
    std::ofstream os(tmp, std::ios::binary | std::ios::trunc);
    if (!os) throw ImageError(fmt::format("cannot create temp file '{}': {}", tmp, std::strerror(errno)));
    {
      Imf::StdOFStream stream(os, tmp.c_str());
      Imf::OutputFile file(stream, header);
      Imf::FrameBuffer fb;
      for (const ExrSlice& s : slices)
        fb.insert(s.name, Imf::Slice(Imf::FLOAT, const_cast<char*>(reinterpret_cast<const char*>(s.base)), s.x_stride,
                                     s.x_stride * size_t(width)));
      file.setFrameBuffer(fb);
      file.writePixels(height);
    }
    os.close();
    if (!os) throw ImageError(fmt::format("error writing temp file '{}'", tmp));
  });
}
}  // namespace

void write_exr(const std::string& path, const Image& img,
               const std::vector<std::pair<std::string, std::string>>& metadata) {
  const char* fn = "write_exr";
  check_image_shape(fn, path, img);
  const float* base = reinterpret_cast<const float*>(img.pixels.data());
  write_exr_slices(fn, path, img.width, img.height,
                   {{"R", base, sizeof(Rgb)}, {"G", base + 1, sizeof(Rgb)}, {"B", base + 2, sizeof(Rgb)}}, metadata);
}

void write_exr_channels(const std::string& path, int width, int height,
                        const std::vector<std::pair<std::string, std::vector<float>>>& channels,
                        const std::vector<std::pair<std::string, std::string>>& metadata) {
  const char* fn = "write_exr_channels";
  if (width <= 0 || height <= 0 || channels.empty()) fail(fn, path, fmt::format("empty image ({}x{}, {} channels)", width, height, channels.size()));
  std::vector<ExrSlice> slices;
  for (const auto& [name, values] : channels) {
    if (values.size() != size_t(width) * size_t(height))
      fail(fn, path, fmt::format("channel '{}' has {} values, not {}x{}", name, values.size(), width, height));
    slices.push_back({name, values.data(), sizeof(float)});
  }
  write_exr_slices(fn, path, width, height, slices, metadata);
}

std::vector<std::pair<std::string, std::string>> read_exr_metadata(const std::string& path) {
  const char* fn = "read_exr_metadata";
  check_readable(fn, path);
  std::vector<std::pair<std::string, std::string>> out;
  try {
    Imf::InputFile file(path.c_str());
    const Imf::Header& header = file.header();
    for (auto it = header.begin(); it != header.end(); ++it)
      if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&it.attribute())) out.emplace_back(it.name(), s->value());
  } catch (const std::exception& e) {
    fail(fn, path, fmt::format("malformed OpenEXR file: {}", e.what()));
  }
  return out;
}

void write_png(const std::string& path, const Image& img) {
  const char* fn = "write_png";
  check_image_shape(fn, path, img);
  std::vector<unsigned char> bytes(img.pixels.size() * 3);
  for (size_t i = 0; i < img.pixels.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      float v = img.pixels[i][c];
      v = std::isnan(v) ? 0.0f : std::clamp(v, 0.0f, 1.0f);
      bytes[3 * i + size_t(c)] = (unsigned char)std::lround(v * 255.0f);
    }
  atomic_write(fn, path, [&](const std::string& tmp) {
    if (!stbi_write_png(tmp.c_str(), img.width, img.height, 3, bytes.data(), img.width * 3))
      throw ImageError(fmt::format("stb_image_write could not write temp file '{}'", tmp));
  });
}

void write_text_file_atomic(const std::string& path, const std::string& text) {
  atomic_write("write_text_file_atomic", path, [&](const std::string& tmp) {
    std::ofstream os(tmp, std::ios::binary | std::ios::trunc);
    if (!os) throw ImageError(fmt::format("cannot create temp file '{}': {}", tmp, std::strerror(errno)));
    os.write(text.data(), std::streamsize(text.size()));
    os.close();
    if (!os) throw ImageError(fmt::format("error writing temp file '{}'", tmp));
  });
}

}  // namespace rl
