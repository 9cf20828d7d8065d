#define GL_GLEXT_PROTOTYPES 1  // libGL exports the OpenGL 3.3 entry points the shader path uses
#include "viewer/gui/display_gl.h"

#include <GLFW/glfw3.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace rl::viewer {

namespace {

const char* kVertex = R"(#version 330 core
void main() {  // one triangle over the viewport
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
})";

// tonemap_pixel (image/tonemap.cpp), step by step, in float: exposure, negative and NaN to 0,
// the operator (Reinhard et al. 2002 eqs. 3 and 4 on Rec. 709 luminance; Narkowicz 2015's ACES
// fit per channel), clamp to [0, 1], sRGB (IEC 61966-2-1).
const char* kFragment = R"(#version 330 core
uniform sampler2D hdr;
uniform float scale;
uniform int op;
uniform float white;
uniform int srgb;
out vec4 color;
float encode(float v) { return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055; }
vec3 aces(vec3 x) { return x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14); }
void main() {
  vec3 c = texelFetch(hdr, ivec2(gl_FragCoord.xy), 0).rgb * scale;
  c = mix(c, vec3(0.0), isnan(c));
  c = clamp(c, 0.0, 1e30);
  if (op == 1 || op == 2) {
    float l = dot(c, vec3(0.2126, 0.7152, 0.0722));
    float ld = op == 1 ? l / (1.0 + l) : l * (1.0 + l / (white * white)) / (1.0 + l);
    c = l > 0.0 ? c * (ld / l) : vec3(0.0);
  } else if (op == 3) {
    c = aces(c);
  }
  c = clamp(c, 0.0, 1.0);
  if (srgb != 0) c = vec3(encode(c.r), encode(c.g), encode(c.b));
  color = vec4(c, 1.0);
})";

unsigned compile(unsigned kind, const char* src) {
  const unsigned s = glCreateShader(kind);
  glShaderSource(s, 1, &src, nullptr);
  glCompileShader(s);
  int ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[1024] = "";
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    std::fprintf(stderr, "warning: view: display shader: %s; tone mapping on the CPU\n", log);
    glDeleteShader(s);
    return 0;
  }
  return s;
}

}  // namespace

GlDisplay::~GlDisplay() {
  if (program_) glDeleteProgram(program_);
  if (vao_) glDeleteVertexArrays(1, &vao_);
  if (fbo_) glDeleteFramebuffers(1, &fbo_);
  if (hdr_) glDeleteTextures(1, &hdr_);
  if (output_) glDeleteTextures(1, &output_);
}

bool GlDisplay::init() {
  glGenTextures(1, &output_);
  glBindTexture(GL_TEXTURE_2D, output_);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  // Nearest: at a render scale below 1 the pixels stay visible as what was rendered.
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  if (std::getenv("RESTIR_VIEW_CPU_DISPLAY")) return false;  // to compare the two paths
  const unsigned vs = compile(GL_VERTEX_SHADER, kVertex), fs = compile(GL_FRAGMENT_SHADER, kFragment);
  if (!vs || !fs) return false;
  program_ = glCreateProgram();
  glAttachShader(program_, vs);
  glAttachShader(program_, fs);
  glLinkProgram(program_);
  glDeleteShader(vs);
  glDeleteShader(fs);
  int ok = 0;
  glGetProgramiv(program_, GL_LINK_STATUS, &ok);
  if (!ok) {
    std::fprintf(stderr, "warning: view: the display shader does not link; tone mapping on the CPU\n");
    glDeleteProgram(program_);
    program_ = 0;
    return false;
  }
  glGenVertexArrays(1, &vao_);
  glGenFramebuffers(1, &fbo_);
  glGenTextures(1, &hdr_);
  glBindTexture(GL_TEXTURE_2D, hdr_);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  return true;
}

void GlDisplay::resize(int w, int h) {
  if (w == width_ && h == height_) return;
  width_ = w;
  height_ = h;
  glBindTexture(GL_TEXTURE_2D, output_);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  if (!program_) return;
  glBindTexture(GL_TEXTURE_2D, hdr_);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB32F, w, h, 0, GL_RGB, GL_FLOAT, nullptr);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, output_, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void GlDisplay::show_hdr(const Image& hdr, const OutputOptions& o) {
  static_assert(sizeof(Rgb) == 3 * sizeof(float), "the HDR upload reads Image pixels as float RGB");
  resize(hdr.width, hdr.height);
  glBindTexture(GL_TEXTURE_2D, hdr_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, hdr.width, hdr.height, GL_RGB, GL_FLOAT, hdr.pixels.data());
  // Row 0 of the image is texture row 0 and output row 0: ImGui draws both with v = 0 at the top.
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glViewport(0, 0, hdr.width, hdr.height);
  glDisable(GL_BLEND);
  glDisable(GL_SCISSOR_TEST);
  glUseProgram(program_);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, hdr_);
  glUniform1i(glGetUniformLocation(program_, "hdr"), 0);
  glUniform1f(glGetUniformLocation(program_, "scale"), std::exp2(o.exposure));
  glUniform1i(glGetUniformLocation(program_, "op"), int(o.tonemap));
  glUniform1f(glGetUniformLocation(program_, "white"), o.white_point);
  glUniform1i(glGetUniformLocation(program_, "srgb"), o.srgb ? 1 : 0);
  glBindVertexArray(vao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glUseProgram(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void GlDisplay::show_ldr(const Image& ldr) {
  resize(ldr.width, ldr.height);
  std::vector<uint8_t> bytes(ldr.size() * 4, 255);
  for (size_t i = 0; i < ldr.size(); ++i)
    for (int c = 0; c < 3; ++c) bytes[i * 4 + size_t(c)] = uint8_t(std::clamp(ldr.pixels[i][c], 0.0f, 1.0f) * 255 + 0.5f);
  glBindTexture(GL_TEXTURE_2D, output_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, ldr.width, ldr.height, GL_RGBA, GL_UNSIGNED_BYTE, bytes.data());
}

int GlDisplay::max_difference(const Image& ldr) const {
  if (!program_ || ldr.width != width_ || ldr.height != height_) return 0;
  std::vector<uint8_t> px(size_t(width_) * size_t(height_) * 4);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, px.data());
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  int worst = 0;
  for (size_t i = 0; i < ldr.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const int cpu = int(std::clamp(ldr.pixels[i][c], 0.0f, 1.0f) * 255 + 0.5f);
      worst = std::max(worst, std::abs(cpu - int(px[i * 4 + size_t(c)])));
    }
  return worst;
}

}  // namespace rl::viewer
