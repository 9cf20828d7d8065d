// ReSTIR PT's path samples and shift mappings (Lin et al. 2022, "Generalized resampled importance
// sampling: foundations of ReSTIR", §5-7).
//
// A path x̄ = (x_1, ..., x_n) starts at the pixel's primary hit x_1 and ends on an emitter x_n (a
// point on an area light, a point or spot light, an environment direction, or a distant light's
// direction). It is parameterized by the solid angles of the directions sampled at x_1..x_{n-2} (or
// x_{n-1} for BSDF-terminated paths) and the emitter point's area (solid angle for the environment,
// counting for the delta lights): f(x̄) = Π f_s|cos| × Le × G.
// Each path carries how its last vertex was sampled (NEE or BSDF — "tag" t), and the integrand of
// the tagged space is m_t(x̄) f(x̄) with the balance heuristic m_t over the two strategies, so that
// the tags partition ∫ f exactly (GRIS with per-path strategies).
//
// Shifts from a base path x̄ to a pixel whose primary hit is y_1:
//   random replay  re-traces the walk from y_1 with the base path's random numbers; the map is the
//                  identity in primary sample space, so |∂ȳ/∂x̄| = p(x̄) / p(ȳ) (GRIS §6.1).
//   reconnection   keeps x_2..x_n and connects y_1 to x_2 (k = 2).
//   hybrid         replays y_2..y_{k-1}, then connects y_{k-1} to x_k, where k is the first vertex
//                  with x_{k-1}, x_k both rough and |x_k - x_{k-1}| >= distance threshold (GRIS §7.2).
//   Reconnection jacobian (solid angle at x_{k-1} -> at y_{k-1}, x_k fixed; ReSTIR GI eq. 11):
//     |cos θ_k^y| / |cos θ_k^x| · |x_k − x_{k−1}|² / |x_k − y_{k−1}|²,  and 1 when x_k is the emitter
//     vertex (area measure); the replayed prefix contributes the pdf ratio above.
#pragma once
#include <span>
#include <vector>

#include "frame/gbuffer.h"
#include "restir/reservoir.h"

namespace rl {

struct EmbreeTracer;
struct PathWorld;

// Packed exactly (issue 48: compact state): the counters in bytes (n <= pt_detail::kMaxVertices =
// 66), and the fields that only one case of k reads share their storage, each union's member valid
// in the case its comment names (rc and length tell which). A reservoir is 112 bytes.
struct PathSample {
  // Written out: rc_out's initializer, not the compiler, sets the union it shares with rc_normal (a
  // union of Vec3s has no implicit default constructor).
  RESTIR_HD PathSample() {}
  uint64_t seed = 0;       // random stream of the walk (per-vertex streams are derived from it)
  uint8_t length = 0;      // n (0 = no path)
  uint8_t rc = 0;          // reconnection vertex k in [2, n]; 0 = none (pure replay)
  bool nee = false;        // tag: last vertex sampled by next-event estimation (else by the BSDF)
  // Reconnection vertex x_k (valid when rc > 0).
  Vec3 rc_position;        // x_k; the direction for an environment or distant emitter
  // k < n: x_k's surface kept as what identifies it -- its geometry, primitive and barycentrics,
  // from which surface_at (scene_view.h) rebuilds the geometric and shading normals, the material
  // and the texture's reflectance bit for bit, as Lin et al.'s own implementation keeps the
  // reconnection vertex as a packed hit (16 bytes instead of 40: issue 48's 320 bytes of persistent
  // state per pixel). x_k (k >= 2) is always a ray hit of the walk.
  union {
    uint32_t rc_emitter = 0xffffffffu;  // k == n: the emitter x_k is on
    uint32_t rc_geom;                   // k < n: x_k's mesh, or SceneView::sphere_geom()
  };
  uint32_t rc_prim = 0;    // k < n: x_k's triangle or sphere
  Vec2 rc_barycentrics;    // k < n: x_k's barycentrics of vertices 1 and 2 (a triangle)
  union {
    Vec3 rc_out{};         // k < n: ω_k, leaving x_k toward x_{k+1}
    Vec3 rc_normal;        // k == n: the emitter's geometric normal at x_k (zero for delta lights / environment)
  };
  Rgb rc_suffix{0};        // everything after x_k's own BSDF term: Π_{i>k} f_s|cos| × Le G (k < n);
                           // Le G of the last segment as the walk found it (k = n)
  union {
    float rc_mis = 1;           // k < n - 1: m_t of the tail (x_{n-1} is after x_k)
    float rc_tail_light_pdf;    // k >= n - 1: the emitter's NEE density at x_n, to recompute m_t after a shift
  };
  float rc_tail_measure = 0;    // k = n - 1: factor turning a solid-angle pdf at x_k into the emitter's measure
  float rc_geometry = 0;   // k < n: |cos φ| / |x_k − x_{k-1}|² at x_k, this path's half of the
                           // reconnection Jacobian (restir/shift.h); x_{k-1} itself is not kept
  float replay_pdf = 1;    // pdf of the replayed part: directions before x_{k-1} (k > 0), or the
                           // whole path including its last vertex (k = 0)
  Rgb contribution{0};     // m_t(x̄) f(x̄) in the domain the sample currently lives in
};

using PathReservoir = restir::Reservoir<PathSample>;
// The sample's identity for the duplication map (reservoir_chain.h): the walk's random stream, which
// every shift keeps (ReSTIR PT Enhanced, sec. 5: "share the same initial random seed").
RESTIR_HD inline uint64_t duplicate_key(const PathSample& x) { return mix64(x.seed); }
static_assert(sizeof(PathReservoir) <= 112, "ReSTIR PT's reservoir outgrew 112 bytes (bench_scaling prints its size)");

// What a walk and a shift read: the path tracer's settings (path.*), so that restir-pt and its
// reference render the same integral, and ReSTIR PT's own (pt.*) -- the option structs themselves,
// no second copy of a field or a default.
struct PathSettings {
  PathOptions path;
  PtOptions pt;
  int min_length = 2;  // shortest path offered (3 when direct lighting comes from ReSTIR DI)
  // Tests only: false removes the hybrid shift's invertibility check, a planted bias that the
  // convergence harness must detect (tests/integrators/test_planted_bias.cpp). Never false in a render.
  bool check_invertibility = true;
  // Tests only: false tests a criterion that depends on the direction into x_k (pt.reconnection =
  // footprint, pt.roughness_proxy = pdf) on the base path only, never on the offset path
  // (PlantedBias::criterion_one_sided). Never false in a render.
  bool retest_on_offset = true;
  // Tests only: false applies pt.force_nee_reconnection in the walks (the base path's choice of x_k)
  // but not in the shifts' criterion on the offset path (PlantedBias::forced_nee_one_sided).
  bool retest_forced_nee = true;
  // Tests only: true keeps roulette's survival probabilities in the densities a shift replays under
  // pt.roulette = initial, whose shifts replay without roulette (PlantedBias::roulette_in_replay).
  bool roulette_in_replay = false;
  // Tests only: true offers the point resampled by pt.nee_candidates > 1 with its source density
  // instead of its RIS contribution weight (PlantedBias::nee_source_density).
  bool nee_source_density = false;
};
PathSettings path_settings(const Options& o);

// Russian roulette's survival probability after reaching a vertex with this BSDF (pt.roulette =
// replayed): its albedo
// (max component; 1 for dielectrics; about F0 + (1 - F0) R for coated diffuse). A property of the vertex alone, so that reconnection shifts,
// which keep the suffix's vertices, keep its roulette decisions too (see pt_path.cpp).
RESTIR_HD inline float roulette_survival(const Bsdf& b) {
  switch (b.type) {
    case Material::Type::diffuse: return std::min(1.0f, max_component(b.reflectance));
    case Material::Type::conductor: return std::min(1.0f, max_component(bsdf_conductor_fresnel(b, 1.0f)));
    case Material::Type::dielectric: return 1.0f;
    case Material::Type::coated_diffuse: {  // normal-incidence albedo, about: F0 + (1 - F0) R
      const float f0 = fresnel_dielectric(1.0f, b.ior);
      return std::min(1.0f, f0 + (1 - f0) * max_component(b.reflectance));
    }
  }
  return 1.0f;
}

// Every path that one walk with random stream walk_seed offers from s, as PathSamples (tests: the
// reconnection index a pixel's own walk assigns to a path, against the one a shift carries).
std::vector<PathSample> walk_paths(const PathWorld& world, const EmbreeTracer& tracer, const PathSettings& ps, const GSurface& s,
                                   uint64_t walk_seed);

// pt.direct = restir-di: renders this frame of `direct` (ReSTIR DI on the same primary rays) and
// adds it to `out`; its stages are recorded in frame.stages as "di.<stage>". rerender: frame is the
// previous frame, rendered again (Integrator::rerender_previous).
void add_direct_light(Integrator& direct, const FrameInfo& frame, Image& out, bool rerender = false);

// The reconnection-depth debug view's histogram of one chain's final reservoirs (k = 0: no
// reconnection), one line on stderr.
void print_reconnection_histogram(int frame, int chain, std::span<const PathReservoir> reservoirs);

}  // namespace rl
