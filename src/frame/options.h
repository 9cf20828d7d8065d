// Every user-facing option of a render, listed once in visit_options(). That single list drives
// the CLI (--set key=value), JSON configs, --help, the config echo, EXR/JSON metadata and CSV
// columns. Keys are the dotted struct paths: "path.max_depth" <-> options.path.max_depth.
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "backends/bvh_layout.h"
#include "core/option_io.h"
#include "image/tonemap_options.h"
#include "restir/mis.h"
#include "scene/light_selection.h"

namespace rl {

enum class SamplePattern { center, stratified, halton, msaa, random };
// Where the frame's stages run (ARCHITECTURE.md, "Backends"): the CPU (Embree), CUDA, or the CUDA
// backend's code on the CPU's threads (its own BVH, host memory): a GPU-less check of the GPU path.
enum class Backend { cpu, cuda, cpu_bvh };
enum class PixelFilter { box, triangle, gaussian };
// How the ReSTIR reuse passes trace their shadow rays (frame/ray_slots.h): each thread its own, or
// recorded by a first run of the pass, traced in one stage and read back by the pass.
enum class ReuseRays { inline_rays, queued };
enum class MisHeuristic { balance, power };
// ReSTIR GI's target function (Ouyang et al. 2021, §4): the sample point's outgoing radiance, or
// that times the BSDF and cosine at the visible point.
enum class GiTarget { radiance, contribution };
// Where ReSTIR PT's direct lighting (paths of one bounce) comes from.
enum class DirectLighting { path, restir_di };
// ReSTIR PT shift mappings (Lin et al. 2022, §5-6).
enum class ShiftMapping { reconnection, random_replay, hybrid };
// The hybrid shift's reconnection criterion: 2022's (both vertices rough, the segment long enough;
// GRIS §7.2) or ReSTIR PT Enhanced's dual ray footprint (Lin, Kettunen, Wyman 2026, sec. 4, eq. 5).
enum class Reconnection { roughness_distance, footprint };
// What "rough" means in the hybrid shift's criteria: the BSDF's roughness parameter, or, for a
// material known only by its sampling density (a black box), 1/p(ω)² of the direction the path
// leaves the vertex by (ReSTIR PT Enhanced, Lin, Kettunen, Wyman 2026, supplement §4, eq. 26).
enum class RoughnessProxy { material, pdf };
// ReSTIR PT's Russian roulette: part of the primary sample space, replayed by every shift
// (survival = the vertex's albedo, which a reconnection keeps), or at initial sampling only, its
// survival probabilities in the initial sample's source density and the shifts deterministic
// (ReSTIR PT Enhanced, Lin, Kettunen, Wyman 2026, sec. 6.2.4; survival on the throughput).
enum class Roulette { replayed, initial };
enum class SsrFallback { environment, none };
// Animated scenes: which frame's scene gives the temporal history its target in the resampling
// MIS weights (the previous frame's: unbiased, GRIS; this frame's: a named biased shortcut).
enum class HistoryScene { previous, current };
// Spatial reuse's neighbours: a spiral per pixel (each pixel shifts to and from each neighbour),
// or reciprocal pairs from pairing textures (each pair's shifts made once; ReSTIR PT Enhanced).
enum class SpatialPairing { none, paired };
// Debug views replace the radiance of ReSTIR integrators with a per-pixel diagnostic.
enum class DebugView { none, confidence, reuse_source, rejected_shifts, reconnection_depth };
// The post-process stage over each finished frame (src/post/, docs/denoise.md). Only methods that
// are implemented are listed: a value that would do nothing is refused by the parser.
enum class DenoiseMethod { none, svgf, asvgf, oidn };

template <> struct EnumNames<SamplePattern> {
  static constexpr std::array<std::pair<SamplePattern, const char*>, 5> values{{{SamplePattern::center, "center"},
      {SamplePattern::stratified, "stratified"}, {SamplePattern::halton, "halton"}, {SamplePattern::msaa, "msaa"},
      {SamplePattern::random, "random"}}};
};
template <> struct EnumNames<Backend> {
  static constexpr std::array<std::pair<Backend, const char*>, 3> values{
      {{Backend::cpu, "cpu"}, {Backend::cuda, "cuda"}, {Backend::cpu_bvh, "cpu-bvh"}}};
};
template <> struct EnumNames<BvhLayout> {
  static constexpr std::array<std::pair<BvhLayout, const char*>, 2> values{{{BvhLayout::binary, "binary"}, {BvhLayout::wide, "wide"}}};
};
template <> struct EnumNames<ReuseRays> {
  static constexpr std::array<std::pair<ReuseRays, const char*>, 2> values{{{ReuseRays::inline_rays, "inline"}, {ReuseRays::queued, "queued"}}};
};
template <> struct EnumNames<PixelFilter> {
  static constexpr std::array<std::pair<PixelFilter, const char*>, 3> values{
      {{PixelFilter::box, "box"}, {PixelFilter::triangle, "triangle"}, {PixelFilter::gaussian, "gaussian"}}};
};
template <> struct EnumNames<MisHeuristic> {
  static constexpr std::array<std::pair<MisHeuristic, const char*>, 2> values{
      {{MisHeuristic::balance, "balance"}, {MisHeuristic::power, "power"}}};
};
template <> struct EnumNames<DebugView> {
  static constexpr std::array<std::pair<DebugView, const char*>, 5> values{
      {{DebugView::none, "none"}, {DebugView::confidence, "confidence"}, {DebugView::reuse_source, "reuse-source"},
       {DebugView::rejected_shifts, "rejected-shifts"}, {DebugView::reconnection_depth, "reconnection-depth"}}};
};
template <> struct EnumNames<SpatialPairing> {
  static constexpr std::array<std::pair<SpatialPairing, const char*>, 2> values{
      {{SpatialPairing::none, "none"}, {SpatialPairing::paired, "paired"}}};
};
template <> struct EnumNames<DenoiseMethod> {
  static constexpr std::array<std::pair<DenoiseMethod, const char*>, 4> values{
      {{DenoiseMethod::none, "none"}, {DenoiseMethod::svgf, "svgf"}, {DenoiseMethod::asvgf, "asvgf"}, {DenoiseMethod::oidn, "oidn"}}};
};
template <> struct EnumNames<GiTarget> {
  static constexpr std::array<std::pair<GiTarget, const char*>, 2> values{
      {{GiTarget::radiance, "radiance"}, {GiTarget::contribution, "contribution"}}};
};
template <> struct EnumNames<DirectLighting> {
  static constexpr std::array<std::pair<DirectLighting, const char*>, 2> values{
      {{DirectLighting::path, "path"}, {DirectLighting::restir_di, "restir-di"}}};
};
template <> struct EnumNames<HistoryScene> {
  static constexpr std::array<std::pair<HistoryScene, const char*>, 2> values{
      {{HistoryScene::previous, "previous"}, {HistoryScene::current, "current"}}};
};
template <> struct EnumNames<SsrFallback> {
  static constexpr std::array<std::pair<SsrFallback, const char*>, 2> values{
      {{SsrFallback::environment, "environment"}, {SsrFallback::none, "none"}}};
};
template <> struct EnumNames<ShiftMapping> {
  static constexpr std::array<std::pair<ShiftMapping, const char*>, 3> values{
      {{ShiftMapping::reconnection, "reconnection"}, {ShiftMapping::random_replay, "random-replay"},
       {ShiftMapping::hybrid, "hybrid"}}};
};
template <> struct EnumNames<Reconnection> {
  static constexpr std::array<std::pair<Reconnection, const char*>, 2> values{
      {{Reconnection::roughness_distance, "roughness-distance"}, {Reconnection::footprint, "footprint"}}};
};
template <> struct EnumNames<RoughnessProxy> {
  static constexpr std::array<std::pair<RoughnessProxy, const char*>, 2> values{{{RoughnessProxy::material, "material"}, {RoughnessProxy::pdf, "pdf"}}};
};
template <> struct EnumNames<Roulette> {
  static constexpr std::array<std::pair<Roulette, const char*>, 2> values{{{Roulette::replayed, "replayed"}, {Roulette::initial, "initial"}}};
};

template <> struct EnumNames<restir::ReuseMis> {
  static constexpr std::array<std::pair<restir::ReuseMis, const char*>, 6> values{
      {{restir::ReuseMis::constant, "constant"},
       {restir::ReuseMis::one_over_z, "one-over-z"},
       {restir::ReuseMis::generalized_balance, "generalized-balance"},
       {restir::ReuseMis::pairwise, "pairwise"},
       {restir::ReuseMis::symmetric_ratio, "symmetric-ratio"},
       {restir::ReuseMis::asymmetric_ratio, "asymmetric-ratio"}}};
};

struct FilmOptions {
  int width = 640;
  int height = 360;
  PixelFilter filter = PixelFilter::box;
  float filter_radius = 0.5f;
};

struct RenderOptions {
  int spp = 4;
  uint64_t seed = 0;
  int frames = 1;
  int threads = 0;
  Backend backend = Backend::cpu;
  BvhLayout bvh = BvhLayout::binary;
  ReuseRays reuse_rays = ReuseRays::inline_rays;
  SamplePattern sample_pattern = SamplePattern::halton;
  LightSelection light_selection = LightSelection::power;
  std::string camera_path;
  DebugView debug_view = DebugView::none;
};

// The light transport every integrator renders (pt, restir-gi, restir-pt; restir-di is direct light,
// depth 1, by definition): one path length, one NEE / BSDF-sampling / roulette setting, so that an
// integrator and its reference always estimate the same integral.
struct PathOptions {
  int max_depth = 5;
  bool nee = true;
  bool bsdf_sampling = true;
  MisHeuristic mis = MisHeuristic::power;
  bool russian_roulette = true;
  int rr_min_depth = 3;
};

// Spatiotemporal reuse, shared by ReSTIR DI, GI and PT (one struct, listed once by visit_reuse;
// its keys sit directly under the integrator's prefix: di.temporal, pt.spatial_radius, ...).
struct ReuseOptions {
  bool temporal = true;
  int max_history = 20;
  restir::ReuseMis temporal_mis = restir::ReuseMis::generalized_balance;
  int spatial_neighbors = 3;
  float spatial_radius = 20;
  int spatial_rounds = 1;
  restir::ReuseMis spatial_mis = restir::ReuseMis::pairwise;
  float mis_ratio_exponent = 2;  // β of the ratio MIS weights (Pan et al. 2024)
  SpatialPairing spatial_pairing = SpatialPairing::none;
  float boiling_filter = 0;  // RTXDI's boiling filter strength (0: off; biased)
  bool duplication_map = false;  // ReSTIR PT Enhanced's duplication maps cap the history (biased)
  bool rgb_weights = false;      // shade with the last spatial round's RGB resampling weights (sec. 6.3)
  bool similarity_rejection = true;
  float depth_threshold = 0.1f;
  float normal_threshold = 25;
};

// ReSTIR DI (Bitterli et al. 2020). Reservoirs hold points on emitters (area measure), directions
// of the environment (solid angle) or point lights, so reuse across pixels is the identity shift.
struct DiOptions {
  int light_candidates = 32;
  int bsdf_candidates = 1;
  int light_tiles = 128;       // pre-sampled light tiles per frame (0: candidates select from all emitters)
  int light_tile_size = 1024;  // emitters per tile
  int env_tile_size = 1024;    // presampled environment directions per tile (0: sampled per candidate)
  bool visibility_reuse = true;
  bool neighbor_visibility = true;
  HistoryScene history_scene = HistoryScene::previous;
  ReuseOptions reuse{.spatial_neighbors = 5, .spatial_radius = 30};
};

// ReSTIR GI (Ouyang et al. 2021): samples are secondary hits with their cached outgoing radiance.
struct GiOptions {
  GiTarget target = GiTarget::contribution;
  ReuseOptions reuse;
};

// ReSTIR PT (Lin et al. 2022, "Generalized resampled importance sampling: foundations of ReSTIR").
struct PtOptions {
  ShiftMapping shift = ShiftMapping::hybrid;
  float roughness_threshold = 0.2f;
  float distance_threshold = 0.1f;
  Reconnection reconnection = Reconnection::roughness_distance;
  float footprint_threshold = 0.02f;      // the paper's c (eq. 5: footprints >= c/100 x the primary footprint)
  float footprint_min_roughness = 0.2f;   // alpha_min at x_{k-1} (sec. 4.2), GGX roughness as roughness_threshold
  RoughnessProxy roughness_proxy = RoughnessProxy::material;  // what the roughness thresholds compare (supplement §4)
  bool force_nee_reconnection = false;    // an NEE path with no earlier reconnection vertex reconnects at its light vertex (sec. 6.2.3)
  Roulette roulette = Roulette::replayed;
  int nee_candidates = 1;                 // light points resampled per NEE (sec. 6.1's RIS inside the path); 1 = one light sample
  bool replay_compaction = false;         // paired reuse: shifts that replay a prefix in a pass of their own (sec. 6.2)
  int candidates = 1;
  DirectLighting direct = DirectLighting::path;
  HistoryScene history_scene = HistoryScene::previous;
  ReuseOptions reuse;
};

// Screen-space reflections (integrator ssr; McGuire and Mara 2014's screen-space ray march).
struct SsrOptions {
  int max_steps = 512;            // pixels walked per ray at most
  float thickness = 0.05f;        // a surface is hit when the ray is behind it by at most this x its distance
  int rays = 1;                   // reflection rays per pixel sample
  float roughness_cutoff = 0.3f;  // surfaces up to this roughness (sqrt(alpha_x alpha_y)) get reflections
  SsrFallback fallback = SsrFallback::environment;
  bool hi_z = true;               // march a hierarchical depth buffer (else one probe per pixel)
  int resolve_neighbors = 4;      // neighbours' rays each glossy pixel reuses in the resolve (0 = none)
  float resolve_radius = 4;       // resolve neighbourhood radius in pixels
  bool temporal = false;          // accumulate reflections over frames (reprojected)
  float temporal_alpha = 0.1f;    // weight of the new frame in that running average
};

// The denoiser run after the integrator (never inside it): the raw frame stays what RenderResult
// and the unbiasedness tests see. Defaults: Schied et al. 2017, "Spatiotemporal Variance-Guided
// Filtering", HPG 2017, sec. 4 (alpha = 0.2 for colour and moments, sigma_z = 1, sigma_n = 128,
// sigma_l = 4, five a-trous iterations).
struct DenoiseOptions {
  DenoiseMethod method = DenoiseMethod::none;
  int atrous_iterations = 5;   // a-trous wavelet passes, step 2^i (Schied 2017, sec. 4.3)
  float sigma_z = 1;           // depth edge-stopping, eq. 3's sigma_z
  float sigma_n = 128;         // normal edge-stopping exponent, eq. 4's sigma_n
  float sigma_l = 4;           // luminance edge-stopping, eq. 5's sigma_l
  float alpha = 0.2f;          // colour history blend, sec. 4.1
  float moments_alpha = 0.2f;  // luminance moments history blend, sec. 4.2
  std::string oidn_library;    // oidn: libOpenImageDenoise.so to load (empty: $RESTIR_OIDN_LIBRARY, else the system's)
};

struct Options {
  std::string integrator = "pt";
  FilmOptions film;
  RenderOptions render;
  PathOptions path;
  DiOptions di;
  GiOptions gi;
  PtOptions pt;
  SsrOptions ssr;
  DenoiseOptions denoise;
  OutputOptions output;
  // The keys set explicitly (set_option: the CLI, --config, a study's base and axes, the viewer's
  // panel), each once; not an option itself. Values a scene file gives are not explicit, nor is a
  // --config key whose value is the one already there (an echoed configuration names every group).
  // check_option_groups refuses one that the chosen integrator does not read.
  std::vector<std::string> explicit_keys;
};

// The reuse keys of one integrator ("di", "gi", "pt"); the key text lives for the visitor call.
template <class R, class V>
void visit_reuse(const char* prefix, R& r, V& v) {
  const std::string p = std::string(prefix) + ".";
  v((p + "temporal").c_str(), r.temporal, "reuse the previous frame's reservoirs (reprojected through the previous camera)");
  v((p + "max_history").c_str(), r.max_history, "M-cap: history confidence <= max_history x the current one (0 = no cap)",
    Range{0, 1000000});
  v((p + "temporal_mis").c_str(), r.temporal_mis, "resampling MIS for temporal reuse (generalized-balance = Talbot)");
  v((p + "spatial_neighbors").c_str(), r.spatial_neighbors, "neighbours per spatial round (0 = no spatial reuse)", Range{0, 64});
  v((p + "spatial_radius").c_str(), r.spatial_radius, "spatial reuse radius in pixels", Range{0, 1024});
  v((p + "spatial_rounds").c_str(), r.spatial_rounds, "spatial reuse passes per frame", Range{0, 16});
  v((p + "spatial_mis").c_str(), r.spatial_mis, "resampling MIS for spatial reuse");
  v((p + "mis_ratio_exponent").c_str(), r.mis_ratio_exponent,
    "temporal_mis / spatial_mis = symmetric-ratio or asymmetric-ratio (Pan et al. 2024): the exponent beta of their "
    "similarity d = min(a/b, b/a)^beta of two domains' targets (larger: a neighbour's weight falls faster as its target "
    "differs; unbiased for any beta)",
    Range{0.25, 16});
  v((p + "spatial_pairing").c_str(), r.spatial_pairing,
    "paired: reciprocal neighbours from pairing textures (Lin, Kettunen, Wyman 2026, ReSTIR PT Enhanced sec. 3): a "
    "pixel's partners reuse from it in turn, so each pair's two shifts are made once (half the spatial pass's shifts and "
    "rays); spatial_neighbors textures, Gaussian offsets of sigma = 0.53 x spatial_radius; unbiased; needs spatial_mis = "
    "pairwise, symmetric-ratio or asymmetric-ratio. none: a golden-angle spiral per pixel");
  v((p + "boiling_filter").c_str(), r.boiling_filter,
    "BIASED (named option): RTXDI's boiling filter, strength in (0, 1]: after reuse, a reservoir whose unbiased "
    "contribution weight W exceeds (10 / strength - 9) x the mean nonzero W of its 16x16-pixel block is dropped "
    "(removes the blotches that one rare sample spreads by reuse, and its energy); 0 = off. Measured on many-lights (ReSTIR "
    "DI vs pt): strength 0.2 -0.09 +- 0.06% (not resolved), 1 -3.9% (worst 8x8 block -9.3%); docs/enhanced.md",
    Range{0, 1});
  v((p + "rgb_weights").c_str(), r.rgb_weights,
    "restir-pt, restir-di: shade each pixel with the last spatial round's RGB resampling weights, the sum of "
    "m_i F(Y_i) W_i |J_i| over its inputs, instead of F(Y) W_Y of the one selected sample (ReSTIR PT Enhanced, sec. 6.3): "
    "less colour noise, unbiased, no extra rays; the reservoirs and their reuse are unchanged. Needs spatial reuse, "
    "spatial_mis other than one-over-z, and for restir-di di.visibility_reuse");
  v((p + "duplication_map").c_str(), r.duplication_map,
    "BIASED (named option): duplication maps (Lin, Kettunen, Wyman 2026, sec. 5): after each frame, D = the share of the "
    "288 other pixels in a 17x17 window whose reservoir holds the same sample; next frame's temporal M-cap there becomes "
    "lerp(max_history, 1, D^0.1) (fewer frames of history where reuse has copied one sample over a region: less "
    "blotching, some energy lost). Measured on many-lights (ReSTIR DI vs pt): -0.02 +- 0.06%, not resolved; the paper "
    "reports 3.25% on its hardest scene; docs/enhanced.md",
    Range{});
  v((p + "similarity_rejection").c_str(), r.similarity_rejection, "skip neighbours / history whose depth or normal differ");
  v((p + "depth_threshold").c_str(), r.depth_threshold, "max relative depth difference of a reused pixel", Range{0, 1e6});
  v((p + "normal_threshold").c_str(), r.normal_threshold, "max normal angle (degrees) between a pixel and a reused one",
    Range{0, 180});
}

// The one list. Help texts say what a value means; ranges reject absurd values up front.
template <class O, class V>
void visit_options(O& o, V& v) {
  v("integrator", o.integrator, "integrator: pt (reference path tracer), restir-di (`restir options` lists all)");
  v("film.width", o.film.width, "image width in pixels (default: the scene's Film, else this)", Range{1, 16384});
  v("film.height", o.film.height, "image height in pixels (default: the scene's Film, else this)", Range{1, 16384});
  v("film.filter", o.film.filter, "pixel reconstruction filter, sampled by filter importance sampling");
  v("film.filter_radius", o.film.filter_radius, "filter radius in pixels (box: 0.5 = one pixel)", Range{0, 8});
  v("render.spp", o.render.spp, "samples per pixel per frame", Range{1, 1 << 20});
  v("render.seed", o.render.seed, "random seed; the same seed and options give the same image");
  v("render.frames", o.render.frames, "frames in the sequence (camera animation spans them)", Range{1, 100000});
  v("render.threads", o.render.threads, "worker threads, 0 = all cores (the image does not depend on it)", Range{0, 1024});
  v("render.backend", o.render.backend,
    "where the frame is computed: cpu (Embree, all cores), cuda (an NVIDIA GPU: the scene, its BVH and every stage "
    "on the device; builds with -DRESTIR_CUDA=ON; every integrator) or cpu-bvh (the CUDA backend's "
    "code, its own BVH, on the CPU's cores: slower than cpu, for checking the GPU path on a machine without one)");
  v("render.bvh", o.render.bvh,
    "the tree the cuda and cpu-bvh backends traverse: binary (two boxes a node, nearer child first) or wide (Ylitie et al. "
    "2017's compressed 8-wide nodes: quantized boxes, children ordered per ray octant, a compressed stack); the same "
    "hits either way; cpu uses Embree's own and refuses wide; docs/gpu.md");
  v("render.reuse_rays", o.render.reuse_rays,
    "how the ReSTIR integrators' temporal and spatial passes trace their shadow rays: inline (each pixel's thread traces its "
    "own) or queued (a first run of the pass records each pixel's any-hit rays, one stage traces them all, the pass reads "
    "the answers: on a GPU no thread idles while another traverses); the same image bit for bit either way; docs/gpu.md");
  v("render.sample_pattern", o.render.sample_pattern,
    "primary-ray positions inside a pixel, continued over the frames of a sequence (anti-aliasing over frames): center, "
    "stratified (4x4 strata cycled over frames at 1-8 spp), halton, msaa (Direct3D 8x positions cycled over frames; 16x "
    "from 9 spp), random");
  v("render.light_selection", o.render.light_selection, "how a light is picked: by emitted power (alias table) or uniformly");
  v("render.camera_path", o.render.camera_path, "JSON camera keyframes overriding the scene camera (empty: none)");
  v("render.debug_view", o.render.debug_view,
    "ReSTIR integrators: output a diagnostic instead of radiance: reservoir confidence M, reuse source of the final "
    "sample (0 = own, 1 = temporal, 2 = spatial), the fraction of reuse candidates rejected or whose shift failed, or "
    "(restir-pt) the reconnection vertex k of the final path (0 = none)");
  v("path.max_depth", o.path.max_depth, "maximum path length in bounces (1 = direct lighting): 0 to 1024 for pt and ssr, 1 to 64 for restir-gi and restir-pt (restir-di is depth 1)", Range{0, 1024});
  v("path.nee", o.path.nee, "next-event estimation (light sampling) at each vertex (pt, restir-gi, restir-pt)");
  v("path.bsdf_sampling", o.path.bsdf_sampling, "importance-sample the BSDF; false: cosine hemisphere (thesis fig. 4.7; pt, restir-gi, restir-pt)");
  v("path.mis", o.path.mis, "MIS heuristic combining light and BSDF sampling in pt (restir-pt's path tags use the balance heuristic)");
  v("path.russian_roulette", o.path.russian_roulette, "terminate paths by Russian roulette (pt: on throughput; restir-pt: see pt.roulette)");
  v("path.rr_min_depth", o.path.rr_min_depth, "first bounce at which Russian roulette may terminate", Range{1, 1024});
  v("di.light_candidates", o.di.light_candidates, "initial light-sample candidates per pixel (M)", Range{0, 4096});
  v("di.bsdf_candidates", o.di.bsdf_candidates, "initial BSDF-sample candidates per pixel, MIS-combined with the light candidates", Range{0, 256});
  v("di.light_tiles", o.di.light_tiles, "pre-sampled light tiles per frame (RTXDI; Wyman and Panteleev 2021): each 16x16-pixel block draws its light candidates' emitters from one tile of di.light_tile_size emitters drawn by the selection pmf; unbiased; 0 = select from every emitter", Range{0, 65536});
  v("di.light_tile_size", o.di.light_tile_size, "emitters per light tile (di.light_tiles)", Range{1, 1 << 20});
  v("di.env_tile_size", o.di.env_tile_size, "environment-map directions presampled per light tile (RTXDI's environment presampling): a light candidate that picks the environment takes one of its tile's directions instead of importance-sampling the map itself; unbiased; 0 = sample the map per candidate (needs di.light_tiles > 0)", Range{0, 1 << 20});
  v("di.visibility_reuse", o.di.visibility_reuse, "include visibility in the target: shadow-test the initial sample before reuse (false with BSDF candidates: one shadow ray per light candidate, for the strategies' MIS)");
  v("di.neighbor_visibility", o.di.neighbor_visibility, "with visibility_reuse: trace visibility when evaluating other pixels' targets in MIS (false: biased, cheaper)");
  v("di.history_scene", o.di.history_scene, "animated scenes: the temporal MIS weights evaluate the history's target in the previous frame's scene (its lights; unbiased) or in this frame's (biased: where a light moved or switched on, the history claims samples it could not have drawn and the image darkens)");
  visit_reuse("di", o.di.reuse, v);
  v("gi.target", o.gi.target, "target function: luminance of the sample's radiance, or of BSDF x cosine x radiance");
  visit_reuse("gi", o.gi.reuse, v);
  v("pt.shift", o.pt.shift, "shift mapping for path reuse: reconnect at the first secondary vertex, replay the random numbers, or replay until a rough, distant vertex pair and reconnect");
  v("pt.roughness_threshold", o.pt.roughness_threshold, "hybrid: minimum GGX roughness (sqrt(alpha_x alpha_y); diffuse = 1) of both vertices at a reconnection", Range{0, 1});
  v("pt.distance_threshold", o.pt.distance_threshold, "hybrid: minimum length of the reconnected segment, in world units", Range{0, 1e9});
  v("pt.reconnection", o.pt.reconnection, "hybrid: reconnection criterion: both vertices rough and the segment long enough (2022), or the dual ray footprint of ReSTIR PT Enhanced (sec. 4): the segment's forward and inverse ray footprints both >= pt.footprint_threshold/100 x the primary hit's footprint, and x_{k-1} rough");
  v("pt.footprint_threshold", o.pt.footprint_threshold, "hybrid, pt.reconnection=footprint: the paper's c (default 0.02): a vertex pair reconnects when both ray footprints are >= c/100 x the primary footprint |x1-x0|^2 4pi / |cos|", Range{0, 1e9});
  v("pt.footprint_min_roughness", o.pt.footprint_min_roughness, "hybrid, pt.reconnection=footprint: minimum GGX roughness of x_{k-1} (the paper's single-vertex alpha_min, sec. 4.2)", Range{0, 1});
  v("pt.roughness_proxy", o.pt.roughness_proxy, "hybrid: what pt.roughness_threshold and pt.footprint_min_roughness compare: the BSDF's roughness parameter (material), or 1/p^2 of the sampled direction's solid-angle density at the vertex (pdf: ReSTIR PT Enhanced supplement sec. 4, for black-box materials; a GGX lobe's peak gives 16 pi^2 alpha^4, so 0.2 ~ alpha 0.19), tested on the offset path too; unbiased");
  v("pt.force_nee_reconnection", o.pt.force_nee_reconnection, "hybrid: a path whose last vertex came from next-event estimation and that has no earlier reconnection vertex reconnects at its light vertex whatever the criterion says (ReSTIR PT Enhanced, sec. 6.2.3): a shift never replays light sampling; unbiased");
  v("pt.roulette", o.pt.roulette, "with path.russian_roulette: replayed (part of the primary sample space: every shift replays the decisions, survival = the vertex albedo) or initial (ReSTIR PT Enhanced, sec. 6.2.4: at initial sampling only, survival = max(throughput) as pt's, its probabilities in the initial sample's source density; shifts never terminate a path); both unbiased");
  v("pt.nee_candidates", o.pt.nee_candidates, "light points per next-event estimation, resampled by RIS toward the unshadowed contribution (ReSTIR PT Enhanced's NEE inside the path reservoir, sec. 6.1): one shadow ray for the chosen point, the path weighted by its RIS contribution weight; 1 = one light sample, as pt. Above 1 the light choice has no closed-form density, so no shift may replay it: needs pt.shift=reconnection, or hybrid with pt.force_nee_reconnection=true; unbiased", Range{1, 64});
  v("pt.replay_compaction", o.pt.replay_compaction, "with pt.spatial_pairing=paired: the partners' shifts that must replay a path prefix (random replay; hybrid paths whose reconnection vertex is past x_2) are listed and made in a pass of their own, after the reconnection-only shifts (ReSTIR PT Enhanced's compaction, sec. 6.2: on a GPU the replays stop idling the threads of a warp that only reconnect). The same shifts and the same image; a schedule, not an estimator");
  v("pt.candidates", o.pt.candidates, "initial paths traced per pixel per frame", Range{1, 256});
  v("pt.direct", o.pt.direct, "direct lighting from the resampled paths themselves, or from ReSTIR DI (di.* options) as in the thesis' engine; the paths then start at two bounces");
  v("pt.history_scene", o.pt.history_scene, "animated scenes: temporal reuse shifts paths between frames by random replay, each frame's path traced in that frame's scene (unbiased; needs pt.shift=random-replay, and keeps a second BVH of the previous frame), or evaluates the history in this frame's scene with pt.shift (biased: a reconnected path keeps the previous frame's vertices and cached radiance)");
  visit_reuse("pt", o.pt.reuse, v);
  v("ssr.max_steps", o.ssr.max_steps, "screen-space reflections: pixels a reflection ray walks at most", Range{1, 1 << 16});
  v("ssr.thickness", o.ssr.thickness, "a ray hits a surface when behind it by at most this fraction of its distance from the camera", Range{1e-5, 10});
  v("ssr.rays", o.ssr.rays, "reflection rays per pixel sample", Range{1, 1024});
  v("ssr.roughness_cutoff", o.ssr.roughness_cutoff, "surfaces with roughness (sqrt(alpha_x alpha_y); diffuse = 1) up to this get screen-space reflections, the others their direct light", Range{0, 1});
  v("ssr.fallback", o.ssr.fallback, "what a ray that finds nothing on screen returns: the environment map or nothing");
  v("ssr.hi_z", o.ssr.hi_z, "march a hierarchical depth buffer, skipping cells the ray passes in front of (Uludag 2014); false: one probe per pixel (McGuire and Mara 2014); ssr.max_steps counts cells or probes");
  v("ssr.resolve_neighbors", o.ssr.resolve_neighbors, "stochastic SSR resolve (Stachowiak 2015): a glossy pixel also reuses the rays of this many neighbours, weighted by its own BRDF over their pdf (less noise, some bias); 0 = its own rays only; mirrors use their own", Range{0, 64});
  v("ssr.resolve_radius", o.ssr.resolve_radius, "radius in pixels of the resolve's neighbourhood", Range{0, 256});
  v("ssr.temporal", o.ssr.temporal, "accumulate the reflective pixels over frames: reproject into the previous frame and blend (exponential average; history rejected where depth or normal changed)");
  v("ssr.temporal_alpha", o.ssr.temporal_alpha, "ssr.temporal: weight of the new frame in the running average (1 = no history)", Range{1e-3, 1});
  v("denoise.method", o.denoise.method, "post-process each frame after the integrator: none, svgf (Schied et al. 2017) or asvgf (SVGF "
    "with temporal gradients, Schied et al. 2018: it renders the previous frame again in this frame's scene; "
    "pt and the ReSTIR integrators) or oidn (Intel "
    "Open Image Denoise 2, loaded at run time: denoise.oidn_library); -o, --png and --frame-dir then write the "
    "denoised frame, --average the raw mean; docs/denoise.md");
  v("denoise.atrous_iterations", o.denoise.atrous_iterations, "svgf: a-trous wavelet iterations (step 2^i pixels)", Range{1, 10});
  v("denoise.sigma_z", o.denoise.sigma_z, "svgf: depth edge-stopping (Schied 2017 eq. 3; larger = blur across depth changes)", Range{1e-6, 1e6});
  v("denoise.sigma_n", o.denoise.sigma_n, "svgf: normal edge-stopping exponent (eq. 4; larger = sharper at creases)", Range{0, 1e6});
  v("denoise.sigma_l", o.denoise.sigma_l, "svgf: luminance edge-stopping in standard deviations (eq. 5)", Range{1e-6, 1e6});
  v("denoise.alpha", o.denoise.alpha, "svgf: weight of the new frame in the colour history (1 = no temporal accumulation)", Range{1e-3, 1});
  v("denoise.moments_alpha", o.denoise.moments_alpha, "svgf: weight of the new frame in the luminance-moments history", Range{1e-3, 1});
  v("denoise.oidn_library", o.denoise.oidn_library, "oidn: the OIDN 2 libOpenImageDenoise.so to load, e.g. the pyoidn "
    "wheel's pyoidn/oidn/lib/libOpenImageDenoise.so.2 (empty: $RESTIR_OIDN_LIBRARY, else the system's)");
  v("output.tonemap", o.output.tonemap, "tone mapper for PNG output");
  v("output.exposure", o.output.exposure, "exposure in stops applied before tone mapping", Range{-64, 64});
  v("output.white_point", o.output.white_point, "white point of modified Reinhard (luminance mapped to 1)", Range{1e-3, 1e6});
  v("output.srgb", o.output.srgb, "encode PNG output with the sRGB transfer curve");
}

// Set one option from text; throws OptionError for an unknown key or a bad value.
void set_option(Options& o, std::string_view key, std::string_view value);
// Parse "key=value".
void set_option_assignment(Options& o, std::string_view assignment);
// Apply a JSON object: nested objects ({"path": {"max_depth": 3}}) or dotted keys.
void apply_options_json(Options& o, std::string_view json_text);
void apply_options_file(Options& o, const std::string& path);
// Every option in declaration order as (key, value text).
std::vector<std::pair<std::string, std::string>> option_values(const Options& o);
// Flat JSON object of every option (the config echo written beside each output).
std::string options_to_json(const Options& o, int indent = 2);
// Every option (key, type, default, meaning), or those whose key starts with `prefix`; a prefix no
// key has is an OptionError.
std::string options_help(std::string_view prefix = {});
// Whether `key` was set explicitly (Options::explicit_keys).
bool is_explicit(const Options& o, std::string_view key);
// The path depths an integrator renders, inclusive (validate_options refuses the others).
std::pair<int, int> max_depth_range(std::string_view integrator);
// The sequence a ReSTIR integrator renders when neither render.spp nor render.frames is set.
inline constexpr int kRestirDefaultFrames = 16;
// Fits the values nobody set explicitly to o.integrator and returns one note per change (a line to
// print; a "warning: " one changes nothing): a scene's max depth outside the integrator's range is
// clamped into it; with `sequence` (a `restir render`), a ReSTIR integrator renders 1 spp per frame
// and kRestirDefaultFrames frames unless render.spp or render.frames is explicit, and many spp in
// one frame draws a warning.
std::vector<std::string> fit_defaults_to_integrator(Options& o, bool sequence);
// Checks relations between fields that ranges cannot express (pixel count, etc.), and that every
// key set explicitly is one the integrator reads (check_option_groups, frame/integrator.h).
void validate_options(const Options& o);

}  // namespace rl
