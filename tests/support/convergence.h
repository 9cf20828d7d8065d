// Statistical comparison of an integrator against the reference path tracer (RESTIR-NOTES
// invariant 6): K independent renders (different seeds) are averaged per block of pixels and
// compared with the converged reference within a few standard errors of the K-run spread.
#pragma once
#include <cmath>
#include <string>
#include <vector>

#include "frame/render.h"
#include "test_helpers.h"

namespace rl::test {

struct BlockStats {
  int blocks = 0;
  int outliers = 0;          // blocks where |mean - ref| > z * SE
  double worst_z = 0;        // largest |mean - ref| / SE over the blocks
  double image_mean = 0;     // mean luminance of the K-run average
  double reference_mean = 0;
  double image_se = 0;       // standard error of the image mean over the K runs
  double relative_bias() const { return image_mean / reference_mean - 1; }
};

inline std::vector<double> block_means(const Image& img, int block) {
  const int bx = img.width / block, by = img.height / block;
  std::vector<double> out(size_t(bx) * size_t(by), 0.0);
  for (int y = 0; y < by * block; ++y)
    for (int x = 0; x < bx * block; ++x) out[size_t(y / block) * size_t(bx) + size_t(x / block)] += luminance(img.at(x, y));
  for (double& v : out) v /= double(block * block);
  return out;
}

// Renders `runs` times with seeds 1000 + i and compares the last frames' block means with the
// reference's. The reference's own noise is included through its two halves (seeds 1 and 2).
inline BlockStats compare_to_reference(const Scene& scene, const Options& test_options, const Options& reference_options,
                                       int runs, int block, double z) {
  std::vector<std::vector<double>> per_run;
  for (int i = 0; i < runs; ++i) {
    Options o = test_options;
    o.render.seed = 1000 + uint64_t(i);
    per_run.push_back(block_means(render(scene, o).last, block));
  }
  Options ra = reference_options, rb = reference_options;
  ra.render.seed = 1;
  rb.render.seed = 2;
  const std::vector<double> ref_a = block_means(render(scene, ra).last, block), ref_b = block_means(render(scene, rb).last, block);
  BlockStats st;
  st.blocks = int(ref_a.size());
  std::vector<double> run_means(size_t(runs), 0.0);
  for (size_t b = 0; b < ref_a.size(); ++b) {
    double mean = 0, var = 0;
    for (int i = 0; i < runs; ++i) mean += per_run[size_t(i)][b];
    mean /= runs;
    for (int i = 0; i < runs; ++i) var += (per_run[size_t(i)][b] - mean) * (per_run[size_t(i)][b] - mean);
    var /= (runs - 1);
    const double ref = 0.5 * (ref_a[b] + ref_b[b]);
    const double ref_var = 0.25 * (ref_a[b] - ref_b[b]) * (ref_a[b] - ref_b[b]);  // var of the mean of 2
    const double se = std::sqrt(var / runs + ref_var + 1e-12);
    const double zz = std::fabs(mean - ref) / se;
    st.worst_z = std::max(st.worst_z, zz);
    if (zz > z) ++st.outliers;
    st.image_mean += mean;
    st.reference_mean += ref;
    for (int i = 0; i < runs; ++i) run_means[size_t(i)] += per_run[size_t(i)][b];
  }
  st.image_mean /= st.blocks;
  st.reference_mean /= st.blocks;
  double m = 0, v = 0;
  for (double& r : run_means) {
    r /= st.blocks;
    m += r;
  }
  m /= runs;
  for (double r : run_means) v += (r - m) * (r - m);
  st.image_se = std::sqrt(v / (runs - 1) / runs);
  return st;
}

}  // namespace rl::test
