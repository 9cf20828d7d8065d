// Small vector / matrix math shared by every module. Plain structs, no dependencies, compiled for
// the host and, in the CUDA backend (src/backends/cuda), for the device: RESTIR_HD marks every
// function per-sample code may call (ARCHITECTURE.md, "Backends").
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>

#ifndef RESTIR_HD
#ifdef __CUDACC__
#define RESTIR_HD __host__ __device__
#else
#define RESTIR_HD
#endif
#endif
// A device function nvcc must inline whatever its call sites (a stage's per-pixel function called
// from two kernels, frame/ray_slots.h, stays inlined into each, as with one); the host compiler decides.
#ifdef __CUDACC__
#define RESTIR_FORCE_INLINE __forceinline__
#else
#define RESTIR_FORCE_INLINE
#endif
// A small host function GCC must inline: its unit-growth limits outline even tiny ones in a
// translation unit that grew (measured: ReSTIR GI's shadow-ray construction, 5.8 % of the frame
// once out of line). nvcc inlines such functions by itself.
#ifdef __CUDACC__
#define RESTIR_ALWAYS_INLINE
#else
#define RESTIR_ALWAYS_INLINE [[gnu::always_inline]]
#endif

namespace rl {

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 0.31830988618379067154f;
inline constexpr float kInv2Pi = 0.15915494309189533577f;
inline constexpr float kInv4Pi = 0.07957747154594766788f;
inline constexpr float kInfinity = 1e30f;  // a finite "infinity": stays well-defined in products

// Starts loading the cache line at p (host only; nothing on the device). The instruction itself,
// not __builtin_prefetch: GCC 12 -O2 deleted every __builtin_prefetch of the spatial reuse passes'
// line loop (reuse_pixel.h's prefetch_lines; the binaries of 1a2ef10 and 641712d have none) as
// code without effects. An asm volatile stays.
RESTIR_HD inline void prefetch_line(const void* p) {
#if defined(__CUDA_ARCH__)
  (void)p;
#elif defined(__x86_64__) || defined(__i386__)
  asm volatile("prefetcht0 %0" ::"m"(*static_cast<const char*>(p)));
#else
  __builtin_prefetch(p);
#endif
}

struct Vec2 {
  float x = 0, y = 0;
  constexpr Vec2() = default;
  RESTIR_HD constexpr Vec2(float x_, float y_) : x(x_), y(y_) {}
  RESTIR_HD constexpr float operator[](int i) const { return i == 0 ? x : y; }
};
RESTIR_HD inline constexpr Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
RESTIR_HD inline constexpr Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
RESTIR_HD inline constexpr Vec2 operator*(Vec2 a, float s) { return {a.x * s, a.y * s}; }

struct Vec3 {
  float x = 0, y = 0, z = 0;
  constexpr Vec3() = default;
  RESTIR_HD constexpr explicit Vec3(float s) : x(s), y(s), z(s) {}
  RESTIR_HD constexpr Vec3(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}
  RESTIR_HD constexpr float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  RESTIR_HD float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  RESTIR_HD Vec3& operator+=(Vec3 b) { x += b.x; y += b.y; z += b.z; return *this; }
  RESTIR_HD Vec3& operator-=(Vec3 b) { x -= b.x; y -= b.y; z -= b.z; return *this; }
  RESTIR_HD Vec3& operator*=(Vec3 b) { x *= b.x; y *= b.y; z *= b.z; return *this; }
  RESTIR_HD Vec3& operator*=(float s) { x *= s; y *= s; z *= s; return *this; }
  RESTIR_HD Vec3& operator/=(float s) { float r = 1.0f / s; x *= r; y *= r; z *= r; return *this; }
};
// RGB radiance / reflectance uses the same three-float layout; the alias documents intent.
using Rgb = Vec3;

RESTIR_HD inline constexpr Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
RESTIR_HD inline constexpr Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
RESTIR_HD inline constexpr Vec3 operator-(Vec3 a) { return {-a.x, -a.y, -a.z}; }
RESTIR_HD inline constexpr Vec3 operator*(Vec3 a, Vec3 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
RESTIR_HD inline constexpr Vec3 operator*(Vec3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
RESTIR_HD inline constexpr Vec3 operator*(float s, Vec3 a) { return {a.x * s, a.y * s, a.z * s}; }
RESTIR_HD inline constexpr Vec3 operator/(Vec3 a, float s) { return a * (1.0f / s); }
RESTIR_HD inline constexpr Vec3 operator/(Vec3 a, Vec3 b) { return {a.x / b.x, a.y / b.y, a.z / b.z}; }
RESTIR_HD inline constexpr bool operator==(Vec3 a, Vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
RESTIR_HD inline constexpr float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
RESTIR_HD inline constexpr Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
RESTIR_HD inline float length_squared(Vec3 a) { return dot(a, a); }
RESTIR_HD inline float length(Vec3 a) { return std::sqrt(dot(a, a)); }
RESTIR_HD inline Vec3 normalize(Vec3 a) { return a / length(a); }
RESTIR_HD inline float abs_dot(Vec3 a, Vec3 b) { return std::fabs(dot(a, b)); }
RESTIR_HD inline Vec3 min(Vec3 a, Vec3 b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
RESTIR_HD inline Vec3 max(Vec3 a, Vec3 b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }
RESTIR_HD inline float max_component(Vec3 a) { return std::max(a.x, std::max(a.y, a.z)); }
RESTIR_HD inline float average(Vec3 a) { return (a.x + a.y + a.z) * (1.0f / 3.0f); }
RESTIR_HD inline bool is_black(Vec3 a) { return a.x == 0 && a.y == 0 && a.z == 0; }
RESTIR_HD inline bool is_finite(Vec3 a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }
// Rec. 709 / sRGB-primaries luminance.
RESTIR_HD inline float luminance(Rgb c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }
// Flip v to the hemisphere of n.
RESTIR_HD inline Vec3 face_forward(Vec3 v, Vec3 n) { return dot(v, n) < 0 ? -v : v; }
RESTIR_HD inline Vec3 reflect(Vec3 wo, Vec3 n) { return -wo + 2 * dot(wo, n) * n; }

template <class T>
RESTIR_HD inline constexpr T clamp(T v, T lo, T hi) { return v < lo ? lo : (v > hi ? hi : v); }
RESTIR_HD inline float sqr(float v) { return v * v; }
RESTIR_HD inline float safe_sqrt(float v) { return std::sqrt(std::max(v, 0.0f)); }

// sin(2 pi u) and cos(2 pi u) for u in [0, 1] (a fraction of a turn, as sampling routines draw
// azimuths), within 3e-7 of the exact values. Branch-free (quarter-turn reduction, then the Taylor
// series to x^9 / x^10 on [-pi/4, pi/4], truncation error < 2e-9), so that loops over many angles
// vectorize, which calls to std::sin / std::cos do not (ReSTIR DI's light candidates, di_candidates.h).
RESTIR_HD inline void sincos_turns(float u, float& sin_out, float& cos_out) {
  const int q4 = int(4 * u + 0.5f);  // nearest quarter turn (truncation: u >= 0; SSE2 has it, not floor)
  const float k = float(q4);
  const float x = (u - 0.25f * k) * 6.28318530717958647692f;  // in [-pi/4, pi/4]
  const float x2 = x * x;
  const float s = x * (1 + x2 * (-1.0f / 6 + x2 * (1.0f / 120 + x2 * (-1.0f / 5040 + x2 * (1.0f / 362880)))));
  const float c = 1 + x2 * (-0.5f + x2 * (1.0f / 24 + x2 * (-1.0f / 720 + x2 * (1.0f / 40320 + x2 * (-1.0f / 3628800)))));
  const int q = q4 & 3;  // rotate (c, s) by q quarter turns
  const float cq = q == 0 ? c : q == 1 ? -s : q == 2 ? -c : s;
  const float sq = q == 0 ? s : q == 1 ? c : q == 2 ? -s : -c;
  sin_out = sq;
  cos_out = cq;
}
RESTIR_HD inline float lerp(float t, float a, float b) { return (1 - t) * a + t * b; }
RESTIR_HD inline Vec3 lerp(float t, Vec3 a, Vec3 b) { return (1 - t) * a + t * b; }

// Orthonormal basis around a unit normal (Duff et al. 2017, "Building an Orthonormal Basis, Revisited").
struct Frame {
  Vec3 s, t, n;
  RESTIR_HD static Frame from_normal(Vec3 n) {
    float sign = std::copysign(1.0f, n.z);
    float a = -1.0f / (sign + n.z);
    float b = n.x * n.y * a;
    Frame f;
    f.s = {1 + sign * n.x * n.x * a, sign * b, -sign * n.x};
    f.t = {b, sign + n.y * n.y * a, -n.y};
    f.n = n;
    return f;
  }
  RESTIR_HD Vec3 to_local(Vec3 v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
  RESTIR_HD Vec3 to_world(Vec3 v) const { return s * v.x + t * v.y + n * v.z; }
};

struct Ray {
  Vec3 o, d;
  float tmin = 0, tmax = kInfinity;
};

// Axis-aligned box.
struct Bounds3 {
  Vec3 lo{kInfinity}, hi{-kInfinity};
  RESTIR_HD void extend(Vec3 p) { lo = min(lo, p); hi = max(hi, p); }
  RESTIR_HD void extend(const Bounds3& b) { lo = min(lo, b.lo); hi = max(hi, b.hi); }
  RESTIR_HD bool empty() const { return lo.x > hi.x; }
  RESTIR_HD Vec3 diagonal() const { return hi - lo; }
  RESTIR_HD Vec3 center() const { return (lo + hi) * 0.5f; }
};

// Row-major 4x4 matrix for affine and projective transforms (pbrt's scene transforms).
struct Mat4 {
  float m[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
  static Mat4 identity() { return {}; }
  Mat4 operator*(const Mat4& b) const {
    Mat4 r;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) {
        double s = 0;
        for (int k = 0; k < 4; ++k) s += double(m[i][k]) * b.m[k][j];
        r.m[i][j] = float(s);
      }
    return r;
  }
  Mat4 transposed() const {
    Mat4 r;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) r.m[i][j] = m[j][i];
    return r;
  }
  RESTIR_HD Vec3 apply_point(Vec3 p) const {
    float x = m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3];
    float y = m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3];
    float z = m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3];
    float w = m[3][0] * p.x + m[3][1] * p.y + m[3][2] * p.z + m[3][3];
    return w == 1 ? Vec3{x, y, z} : Vec3{x, y, z} / w;
  }
  RESTIR_HD Vec3 apply_vector(Vec3 v) const {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
  }
  // Normals transform by the inverse transpose; pass the *inverse* matrix here.
  static Vec3 apply_normal_with_inverse(const Mat4& inv, Vec3 n) {
    return {inv.m[0][0] * n.x + inv.m[1][0] * n.y + inv.m[2][0] * n.z,
            inv.m[0][1] * n.x + inv.m[1][1] * n.y + inv.m[2][1] * n.z,
            inv.m[0][2] * n.x + inv.m[1][2] * n.y + inv.m[2][2] * n.z};
  }
  // Determinant of the upper 3x3 (negative: the transform swaps handedness).
  float det3() const {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  }
  // Returns false for a singular matrix.
  bool inverse(Mat4& out) const;
};

Mat4 translate(Vec3 d);
Mat4 scale(Vec3 s);
Mat4 rotate(float degrees, Vec3 axis);
// pbrt's LookAt: returns camera-from-world (left-handed camera space, +z forward).
bool look_at(Vec3 eye, Vec3 target, Vec3 up, Mat4& camera_from_world);

}  // namespace rl
