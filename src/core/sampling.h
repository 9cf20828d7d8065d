// Sampling routines as sample_* / *_pdf pairs. Each pair is chi-square tested in tests/.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "core/math.h"

namespace rl {

RESTIR_HD inline Vec2 sample_uniform_disk_concentric(Vec2 u) {
  // Shirley & Chiu 1997 concentric mapping.
  float ox = 2 * u.x - 1, oy = 2 * u.y - 1;
  if (ox == 0 && oy == 0) return {0, 0};
  float r, th;
  if (std::fabs(ox) > std::fabs(oy)) {
    r = ox;
    th = (kPi / 4) * (oy / ox);
  } else {
    r = oy;
    th = kPi / 2 - (kPi / 4) * (ox / oy);
  }
  return {r * std::cos(th), r * std::sin(th)};
}

// Cosine-weighted hemisphere around +z (Malley's method).
RESTIR_HD inline Vec3 sample_cosine_hemisphere(Vec2 u) {
  Vec2 d = sample_uniform_disk_concentric(u);
  float z = safe_sqrt(1 - d.x * d.x - d.y * d.y);
  return {d.x, d.y, z};
}
RESTIR_HD inline float cosine_hemisphere_pdf(float cos_theta) { return cos_theta > 0 ? cos_theta * kInvPi : 0.0f; }

RESTIR_HD inline Vec3 sample_uniform_sphere(Vec2 u) {
  float z = 1 - 2 * u.x;
  float r = safe_sqrt(1 - z * z);
  float phi = 2 * kPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}
RESTIR_HD inline float uniform_sphere_pdf() { return kInv4Pi; }

RESTIR_HD inline Vec3 sample_uniform_hemisphere(Vec2 u) {
  float z = u.x;
  float r = safe_sqrt(1 - z * z);
  float phi = 2 * kPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}
RESTIR_HD inline float uniform_hemisphere_pdf() { return kInv2Pi; }

// Uniform cone around +z with cos(theta_max).
RESTIR_HD inline Vec3 sample_uniform_cone(Vec2 u, float cos_max) {
  float cos_t = (1 - u.x) + u.x * cos_max;
  float sin_t = safe_sqrt(1 - cos_t * cos_t);
  float phi = u.y * 2 * kPi;
  return {std::cos(phi) * sin_t, std::sin(phi) * sin_t, cos_t};
}
RESTIR_HD inline float uniform_cone_pdf(float cos_max) { return 1 / (2 * kPi * (1 - cos_max)); }

// Uniform barycentrics on a triangle (Heitz 2019, "A Low-Distortion Map Between Triangle and Square").
RESTIR_HD inline Vec3 sample_uniform_triangle(Vec2 u) {
  float b0, b1;
  if (u.x < u.y) {
    b0 = u.x / 2;
    b1 = u.y - b0;
  } else {
    b1 = u.y / 2;
    b0 = u.x - b1;
  }
  return {b0, b1, 1 - b0 - b1};
}

// Tent (triangle filter) on [-r, r]: inverse CDF of the piecewise-linear density.
RESTIR_HD inline float sample_tent(float u, float r) {
  if (u < 0.5f) {
    float v = u * 2;
    return r * (-1 + std::sqrt(v));
  }
  float v = (u - 0.5f) * 2;
  return r * (1 - std::sqrt(1 - v));
}

// Balance and power heuristics for two strategies (Veach 1997, eq. 9.10 and 9.12).
RESTIR_HD inline float balance_heuristic(float pa, float pb) { return pa + pb > 0 ? pa / (pa + pb) : 0.0f; }
RESTIR_HD inline float power_heuristic(float pa, float pb) {
  float a = pa * pa, b = pb * pb;
  if (std::isinf(a)) return 1.0f;
  return a + b > 0 ? a / (a + b) : 0.0f;
}

// Radical inverse of a in the base_index-th prime base (Halton sequence component).
// The digit loop for one base. A base known at compile time turns the 64-bit division into a
// multiplication (a division by a run-time base costs ~40 cycles a digit: the camera rays of the
// Halton pattern spent 11% of a path-traced frame there).
template <uint32_t kBase>
RESTIR_HD inline float radical_inverse_in(uint64_t a) {
  const double inv_base = 1.0 / kBase;
  double inv_base_m = 1.0;
  uint64_t reversed = 0;
  while (a) {
    const uint64_t next = a / kBase;
    const uint64_t digit = a - next * kBase;
    reversed = reversed * kBase + digit;
    inv_base_m *= inv_base;
    a = next;
  }
  return float(std::min(double(reversed) * inv_base_m, double(0x1.fffffep-1)));
}

RESTIR_HD inline float radical_inverse(uint32_t base_index, uint64_t a) {
  switch (base_index % 16u) {  // the primes 2, 3, 5, ..., 53
    case 0: return radical_inverse_in<2>(a);
    case 1: return radical_inverse_in<3>(a);
    case 2: return radical_inverse_in<5>(a);
    case 3: return radical_inverse_in<7>(a);
    case 4: return radical_inverse_in<11>(a);
    case 5: return radical_inverse_in<13>(a);
    case 6: return radical_inverse_in<17>(a);
    case 7: return radical_inverse_in<19>(a);
    case 8: return radical_inverse_in<23>(a);
    case 9: return radical_inverse_in<29>(a);
    case 10: return radical_inverse_in<31>(a);
    case 11: return radical_inverse_in<37>(a);
    case 12: return radical_inverse_in<41>(a);
    case 13: return radical_inverse_in<43>(a);
    case 14: return radical_inverse_in<47>(a);
    default: return radical_inverse_in<53>(a);
  }
}

// Walker / Vose alias table: O(1) sampling of a discrete distribution. Weights need not be
// normalized; zero weights are never sampled.
struct AliasBin {
  float q = 0;      // probability of keeping this bin's own index
  uint32_t alias = 0;
};

// The table's sampling as a flat, trivially copyable view (bins and pmf arrays of `size` entries
// each, owned elsewhere), callable from device code. AliasTable::sample / pmf forward here.
struct AliasTableView {
  const AliasBin* bins = nullptr;
  const float* pmfs = nullptr;  // pmfs[i]: the probability of index i
  uint32_t size = 0;

  // Returns the index; pmf (optional) receives its probability; u in [0,1). u_remapped (optional)
  // receives the part of u left over after the choice, itself uniform in [0,1).
  RESTIR_HD uint32_t sample(float u, float* pmf = nullptr, float* u_remapped = nullptr) const {
    const uint32_t n = size;
    if (n == 0) {
      if (pmf) *pmf = 0;
      return 0;
    }
    float x = u * float(n);
    uint32_t offset = std::min<uint32_t>(uint32_t(x), uint32_t(n - 1));
    float up = std::min(x - float(offset), 0x1.fffffep-1f);
    uint32_t idx;
    if (up < bins[offset].q) {
      idx = offset;
      if (u_remapped) *u_remapped = std::min(up / bins[offset].q, 0x1.fffffep-1f);
    } else {
      idx = bins[offset].alias;
      if (u_remapped) *u_remapped = std::min((up - bins[offset].q) / (1 - bins[offset].q), 0x1.fffffep-1f);
    }
    if (pmf) *pmf = pmfs[idx];
    return idx;
  }
  RESTIR_HD float pmf(uint32_t i) const { return i < size ? pmfs[i] : 0.0f; }
};

class AliasTable {
 public:
  using Bin = AliasBin;
  AliasTable() = default;
  explicit AliasTable(std::span<const float> weights);
  // Returns the index; pmf (optional) receives its probability; u in [0,1). Both forward to view().
  uint32_t sample(float u, float* pmf = nullptr, float* u_remapped = nullptr) const;
  float pmf(uint32_t i) const;
  size_t size() const { return pmf_.size(); }
  double total_weight() const { return total_; }
  // Points into this table's arrays: valid until the table is changed, moved or destroyed.
  AliasTableView view() const { return {bins_.data(), pmf_.data(), uint32_t(pmf_.size())}; }

 private:
  std::vector<Bin> bins_;
  std::vector<float> pmf_;
  double total_ = 0;
};

// Piecewise-constant 1-D and 2-D distributions (pbrt's PiecewiseConstant1D/2D) for env maps.
class Distribution1D {
 public:
  Distribution1D() = default;
  explicit Distribution1D(std::span<const float> f);
  // Continuous sample in [0,1); pdf w.r.t. [0,1); offset = chosen cell.
  float sample_continuous(float u, float* pdf, int* offset = nullptr) const;
  float pdf(float x) const;
  size_t count() const { return func_.size(); }
  float integral() const { return integral_; }

 private:
  std::vector<float> func_, cdf_;
  float integral_ = 0;
};

class Distribution2D {
 public:
  Distribution2D() = default;
  // f is nv rows of nu values (row-major, v = row).
  Distribution2D(std::span<const float> f, int nu, int nv);
  Vec2 sample_continuous(Vec2 u, float* pdf) const;
  float pdf(Vec2 p) const;

 private:
  std::vector<Distribution1D> conditional_;
  Distribution1D marginal_;
};

}  // namespace rl
