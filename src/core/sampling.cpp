#include "core/sampling.h"

#include <numeric>

namespace rl {

AliasTable::AliasTable(std::span<const float> weights) {
  const size_t n = weights.size();
  bins_.assign(n, {});
  pmf_.assign(n, 0.0f);
  total_ = 0;
  for (float w : weights) total_ += std::max(w, 0.0f);
  if (n == 0 || total_ <= 0) {
    bins_.clear();
    pmf_.clear();
    total_ = 0;
    return;
  }
  // Vose's method on p_i * n.
  std::vector<double> scaled(n);
  std::vector<uint32_t> small, large;
  for (size_t i = 0; i < n; ++i) {
    double p = std::max(weights[i], 0.0f) / total_;
    pmf_[i] = float(p);
    scaled[i] = p * double(n);
    (scaled[i] < 1.0 ? small : large).push_back(uint32_t(i));
  }
  while (!small.empty() && !large.empty()) {
    uint32_t s = small.back(), l = large.back();
    small.pop_back();
    large.pop_back();
    bins_[s].q = float(scaled[s]);
    bins_[s].alias = l;
    scaled[l] = (scaled[l] + scaled[s]) - 1.0;
    (scaled[l] < 1.0 ? small : large).push_back(l);
  }
  // Leftovers are 1 up to rounding.
  for (uint32_t i : large) bins_[i] = {1.0f, i};
  for (uint32_t i : small) bins_[i] = {1.0f, i};
}

// Out of line as before: inlined, GCC warns about callers' u_remapped, which an empty table leaves
// unwritten (-Wmaybe-uninitialized in tests/core/test_sampling.cpp).
uint32_t AliasTable::sample(float u, float* pmf, float* u_remapped) const { return view().sample(u, pmf, u_remapped); }

float AliasTable::pmf(uint32_t i) const { return view().pmf(i); }

Distribution1D::Distribution1D(std::span<const float> f) : func_(f.begin(), f.end()), cdf_(f.size() + 1) {
  const size_t n = func_.size();
  for (float& v : func_) v = std::fabs(v);
  cdf_[0] = 0;
  for (size_t i = 1; i <= n; ++i) cdf_[i] = cdf_[i - 1] + func_[i - 1] / float(n);
  integral_ = cdf_[n];
  if (integral_ == 0) {
    for (size_t i = 1; i <= n; ++i) cdf_[i] = float(i) / float(n);
  } else {
    for (size_t i = 1; i <= n; ++i) cdf_[i] /= integral_;
  }
}

float Distribution1D::sample_continuous(float u, float* pdf, int* offset) const {
  const size_t n = func_.size();
  // Largest index with cdf[i] <= u.
  size_t lo = 0, hi = n;
  while (lo + 1 < hi) {
    size_t mid = (lo + hi) / 2;
    if (cdf_[mid] <= u) lo = mid; else hi = mid;
  }
  size_t i = lo;
  if (offset) *offset = int(i);
  float du = u - cdf_[i];
  if (cdf_[i + 1] - cdf_[i] > 0) du /= (cdf_[i + 1] - cdf_[i]);
  if (pdf) *pdf = integral_ > 0 ? func_[i] / integral_ : 1.0f;
  return std::min((float(i) + du) / float(n), 0x1.fffffep-1f);
}

float Distribution1D::pdf(float x) const {
  const size_t n = func_.size();
  if (n == 0 || x < 0 || x >= 1) return 0;
  size_t i = std::min(size_t(x * float(n)), n - 1);
  return integral_ > 0 ? func_[i] / integral_ : 1.0f;
}

Distribution2D::Distribution2D(std::span<const float> f, int nu, int nv) {
  conditional_.reserve(size_t(nv));
  std::vector<float> marginal(static_cast<size_t>(nv));
  for (int v = 0; v < nv; ++v) {
    conditional_.emplace_back(f.subspan(size_t(v) * size_t(nu), size_t(nu)));
    marginal[size_t(v)] = conditional_.back().integral();
  }
  marginal_ = Distribution1D(marginal);
}

Vec2 Distribution2D::sample_continuous(Vec2 u, float* pdf) const {
  float pdfs[2];
  int v;
  float d1 = marginal_.sample_continuous(u.y, &pdfs[1], &v);
  float d0 = conditional_[size_t(v)].sample_continuous(u.x, &pdfs[0]);
  if (pdf) *pdf = pdfs[0] * pdfs[1];
  return {d0, d1};
}

float Distribution2D::pdf(Vec2 p) const {
  if (conditional_.empty()) return 0;
  size_t nv = conditional_.size();
  size_t iv = std::min(size_t(std::max(p.y, 0.0f) * float(nv)), nv - 1);
  if (marginal_.integral() == 0) return 1.0f;
  return conditional_[iv].pdf(p.x) * conditional_[iv].integral() / marginal_.integral();
}

}  // namespace rl
