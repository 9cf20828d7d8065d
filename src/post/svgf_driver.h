// SVGF (Schied et al. 2017) as per-pixel stages over an execution policy (host_exec.h documents
// Exec): the same math as Svgf (svgf_stages.h), one launch per stage -- temporal (steps 1-3:
// geometry, demodulation, reprojection, accumulation), the 7x7 variance estimate, each a-trous
// iteration, re-modulation -- over planar buffers (structure of arrays) in the policy's memory.
// The denoiser of the BVH backends (denoisers.cpp): SvgfStages<HostExec> for render.backend =
// cpu-bvh, the host twin that runs in CI the code CUDA runs; SvgfStages<cuda::CudaExec>
// (svgf_stages.cu) for cuda. It gives Svgf's floats (tests/post/test_svgf_stages.cpp): the
// stages sum each pixel's taps in the order and with the expressions Svgf's vectorised rows use.
// Buffers are reserved once per frame size and swapped between frames, never reallocated.
#pragma once
#include <memory>
#include <utility>
#include <vector>

#include "backends/cpu/host_exec.h"
#include "post/svgf.h"
#include "post/svgf_stages.h"

namespace rl {

namespace svgf_driver {

using namespace svgf;

// The previous frame at pixel j, from planes (reproject's H).
struct PlaneHistory {
  const float *nx, *ny, *nz, *z, *dz;
  const uint32_t* id;
  const float *r, *g, *b, *m1, *m2, *length_;
  RESTIR_HD Geometry geometry(size_t j) const { return {Vec3(nx[j], ny[j], nz[j]), z[j], dz[j], id[j]}; }
  RESTIR_HD Rgb color(size_t j) const { return Rgb(r[j], g[j], b[j]); }
  RESTIR_HD Vec2 moments(size_t j) const { return {m1[j], m2[j]}; }
  RESTIR_HD float length(size_t j) const { return length_[j]; }
};

// Where a stage writes its samples: colour, its luminance (what the next pass's eq. 5 reads; Svgf
// takes it from the same floats) and variance.
struct SampleOut {
  float *r, *g, *b, *l, *var;
  RESTIR_HD void put(size_t i, const Sample& s) const {
    r[i] = s.c.x, g[i] = s.c.y, b[i] = s.c.z, l[i] = luminance(s.c), var[i] = s.var;
  }
  RESTIR_HD void copy(size_t i, const SamplePlanes& in) const {
    r[i] = in.r[i], g[i] = in.g[i], b[i] = in.b[i], l[i] = in.l[i], var[i] = in.var[i];
  }
};

// Steps 1-3 (sec. 4.1-4.2) at one pixel: its geometry planes, its sample, moments and history.
struct TemporalStage {
  int width, height;
  const Rgb *noisy, *albedo, *emission;
  const Vec3* normal;
  const float *depth, *depth_gradient;
  const Vec2* motion;
  const uint32_t* surface_id;
  const float* lambda;  // A-SVGF's (Schied et al. 2018, eq. 9); null: none
  bool has_history;
  PlaneHistory history;
  Params p;
  float *nx, *ny, *nz, *z, *dz, *ipz;
  uint32_t* id;
  SampleOut out;
  float *m1, *m2, *length;
  RESTIR_HD void operator()(int x, int y) const {
    const size_t i = size_t(y) * size_t(width) + size_t(x);
    const Geometry g = make_geometry(normal[i], depth[i], depth_gradient[i], surface_id[i]);
    nx[i] = g.n.x, ny[i] = g.n.y, nz[i] = g.n.z, z[i] = g.z, dz[i] = g.dz, id[i] = g.id;
    ipz[i] = inv_depth_scale(g, p.sigma_z);
    const Temporal t = temporal_pixel(has_history ? &history : nullptr, x, y, width, height, noisy[i], albedo[i], emission[i],
                                      motion[i], g, lambda ? lambda + i : nullptr, p);
    out.put(i, t.s);
    m1[i] = t.moments.x, m2[i] = t.moments.y, length[i] = t.length;
  }
};

// Step 3's 7x7 estimate where the history is shorter than 4 frames; elsewhere the sample as it is.
struct MomentsStage {
  int width, height;
  GeometryPlanes g;
  SamplePlanes in;   // var: the first moment, m2 the second
  const float* var;  // the temporal variance (kept where the history is long enough)
  const float* length;
  Params p;
  SampleOut out;
  RESTIR_HD void operator()(int x, int y) const {
    const size_t i = size_t(y) * size_t(width) + size_t(x);
    if (g.id[i] == kNoSurface || length[i] >= kMinHistoryForTemporalVariance) {
      out.r[i] = in.r[i], out.g[i] = in.g[i], out.b[i] = in.b[i], out.l[i] = in.l[i], out.var[i] = var[i];
      return;
    }
    out.put(i, moments_pixel(g, in, x, y, width, height, length[i], p));
  }
};

// Step 4: one a-trous iteration (eq. 1-5); pixels without a surface pass through.
struct AtrousStage {
  int width, height, step;
  GeometryPlanes g;
  SamplePlanes in;
  Params p;
  SampleOut out;
  RESTIR_HD void operator()(int x, int y) const {
    const size_t i = size_t(y) * size_t(width) + size_t(x);
    if (g.id[i] == kNoSurface) out.copy(i, in);
    else out.put(i, atrous_pixel(g, in, x, y, width, height, step, p));
  }
};

// Step 5: radiance = illumination x albedo + emission; the environment as it came.
struct RemodulateStage {
  int width;
  const Rgb *noisy, *albedo, *emission;
  const uint32_t* id;
  const float *r, *g, *b;
  Rgb* out;
  RESTIR_HD void operator()(int x, int y) const {
    const size_t i = size_t(y) * size_t(width) + size_t(x);
    out[i] = id[i] == kNoSurface ? noisy[i] : remodulate(Rgb(r[i], g[i], b[i]), demodulator(albedo[i]), emission[i]);
  }
};

}  // namespace svgf_driver

template <class Exec>
class SvgfStages : public SvgfFilter {
 public:
  explicit SvgfStages(const DenoiseOptions& o) : p_(svgf::params_of(o)), iterations_(o.atrous_iterations) {}
  void denoise(const Image& noisy, const Aovs& aovs, Image& out) override;
  // Downloaded from the policy's memory when asked for (tests read it).
  const std::vector<float>& history_length() const override {
    length_host_.resize(n_);
    Exec::download(length_host_.data(), length_, n_);
    return length_host_;
  }
  void set_temporal_lambda(std::vector<float> lambda) override { lambda_ = std::move(lambda); }

 private:
  template <class T>
  using Array = typename Exec::template Array<T>;
  struct GeometryBuffers {
    Array<float> nx, ny, nz, z, dz, ipz;
    Array<uint32_t> id;
    void reserve(size_t n) {
      for (Array<float>* a : {&nx, &ny, &nz, &z, &dz, &ipz}) a->reserve(n);
      id.reserve(n);
    }
    void swap(GeometryBuffers& o) {
      nx.swap(o.nx), ny.swap(o.ny), nz.swap(o.nz), z.swap(o.z), dz.swap(o.dz), ipz.swap(o.ipz), id.swap(o.id);
    }
    svgf::GeometryPlanes planes() const { return {nx.data, ny.data, nz.data, z.data, ipz.data, id.data}; }
  };
  struct SampleBuffers {
    Array<float> r, g, b, l, var;
    void reserve(size_t n) {
      for (Array<float>* a : {&r, &g, &b, &l, &var}) a->reserve(n);
    }
    void swap(SampleBuffers& o) { r.swap(o.r), g.swap(o.g), b.swap(o.b), l.swap(o.l), var.swap(o.var); }
    svgf::SamplePlanes planes(const float* m2 = nullptr) const { return {r.data, g.data, b.data, l.data, var.data, m2}; }
    svgf_driver::SampleOut out() { return {r.data, g.data, b.data, l.data, var.data}; }
  };

  struct Inputs {
    const Rgb *noisy, *albedo, *emission;
    const Vec3* normal;
    const float *depth, *depth_gradient;
    const Vec2* motion;
    const uint32_t* surface_id;
    const float* lambda;
  };
  void resize(int width, int height);
  void temporal(const Inputs& in);
  void filter();

  svgf::Params p_;
  int iterations_;
  int width_ = 0, height_ = 0;
  size_t n_ = 0;
  bool has_history_ = false;
  GeometryBuffers geometry_, previous_geometry_;
  SampleBuffers ping_, pong_;
  Array<float> m1_, m2_, history_m1_, history_m2_, length_, previous_length_;
  Array<float> history_r_, history_g_, history_b_;  // the previous frame's first a-trous output (sec. 4.3)
  // The frame's inputs in the policy's memory (HostExec: the host arrays themselves) and its output.
  Array<Rgb> noisy_, albedo_, emission_, out_;
  Array<Vec3> normal_;
  Array<float> depth_, depth_gradient_, lambda_in_;
  Array<Vec2> motion_;
  Array<uint32_t> surface_id_;
  std::vector<float> lambda_;
  mutable std::vector<float> length_host_;
};

template <class Exec>
void SvgfStages<Exec>::resize(int width, int height) {
  width_ = width, height_ = height, n_ = size_t(width) * size_t(height);
  geometry_.reserve(n_), previous_geometry_.reserve(n_);
  ping_.reserve(n_), pong_.reserve(n_);
  for (Array<float>* a : {&m1_, &m2_, &history_m1_, &history_m2_, &length_, &previous_length_, &history_r_, &history_g_, &history_b_})
    a->reserve(n_);
  out_.reserve(n_);
  has_history_ = false;  // a new size: no history
}

template <class Exec>
void SvgfStages<Exec>::temporal(const Inputs& in) {
  const svgf_driver::PlaneHistory history{previous_geometry_.nx.data, previous_geometry_.ny.data, previous_geometry_.nz.data,
                                          previous_geometry_.z.data,  previous_geometry_.dz.data, previous_geometry_.id.data,
                                          history_r_.data,            history_g_.data,            history_b_.data,
                                          history_m1_.data,           history_m2_.data,           previous_length_.data};
  const svgf_driver::TemporalStage stage{width_,          height_,           in.noisy,          in.albedo,         in.emission,
                                         in.normal,       in.depth,          in.depth_gradient, in.motion,         in.surface_id,
                                         in.lambda,       has_history_,      history,           p_,                geometry_.nx.data,
                                         geometry_.ny.data, geometry_.nz.data, geometry_.z.data, geometry_.dz.data, geometry_.ipz.data,
                                         geometry_.id.data, ping_.out(),     m1_.data,          m2_.data,          length_.data};
  Exec::for_pixels(width_, height_, stage, "svgf temporal");
}

// Steps 3-4: the 7x7 estimate (every pixel: those with 4 frames copy theirs), then the a-trous
// iterations; the first one's colour is the next frame's history (sec. 4.3).
template <class Exec>
void SvgfStages<Exec>::filter() {
  const svgf_driver::MomentsStage moments{width_, height_, geometry_.planes(),
                                          {ping_.r.data, ping_.g.data, ping_.b.data, ping_.l.data, m1_.data, m2_.data},
                                          ping_.var.data, length_.data, p_, pong_.out()};
  Exec::for_pixels(width_, height_, moments, "svgf variance");
  ping_.swap(pong_);
  for (int it = 0; it < iterations_; ++it) {
    const svgf_driver::AtrousStage atrous{width_, height_, 1 << it, geometry_.planes(), ping_.planes(), p_, pong_.out()};
    Exec::for_pixels(width_, height_, atrous, "svgf a-trous");
    if (it == 0) {
      Exec::copy(history_r_, pong_.r, n_), Exec::copy(history_g_, pong_.g, n_), Exec::copy(history_b_, pong_.b, n_);
    }
    ping_.swap(pong_);
  }
}

template <class Exec>
void SvgfStages<Exec>::denoise(const Image& noisy, const Aovs& aovs, Image& out) {
  if (noisy.width != width_ || noisy.height != height_) resize(noisy.width, noisy.height);
  previous_length_.swap(length_);
  // The frame's inputs where the stages read them (uploaded once; HostExec: the host arrays).
  const Inputs in{Exec::mirror(noisy_, noisy.pixels.data(), n_), Exec::mirror(albedo_, aovs.albedo.data(), n_),
                  Exec::mirror(emission_, aovs.emission.data(), n_), Exec::mirror(normal_, aovs.normal.data(), n_),
                  Exec::mirror(depth_, aovs.depth.data(), n_), Exec::mirror(depth_gradient_, aovs.depth_gradient.data(), n_),
                  Exec::mirror(motion_, aovs.motion.data(), n_), Exec::mirror(surface_id_, aovs.surface_id.data(), n_),
                  lambda_.empty() ? nullptr : Exec::mirror(lambda_in_, lambda_.data(), n_)};
  temporal(in);
  filter();
  out = Image(width_, height_);
  const svgf_driver::RemodulateStage stage{width_, in.noisy, in.albedo, in.emission, in.surface_id, ping_.r.data, ping_.g.data, ping_.b.data, out_.data};
  Exec::for_pixels(width_, height_, stage, "svgf remodulate");
  Exec::download(out.pixels.data(), out_, n_);
  history_m1_.swap(m1_), history_m2_.swap(m2_);
  previous_geometry_.swap(geometry_);
  has_history_ = true;
}

// SVGF's stages on the CUDA backend (svgf_stages.cu; builds with RESTIR_CUDA=ON): device 0.
std::unique_ptr<SvgfFilter> make_svgf_cuda(const DenoiseOptions& o);

}  // namespace rl
