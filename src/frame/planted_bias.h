// Planted biases: deliberate, small errors in ReSTIR's resampling that the test suite injects to
// prove that its convergence harness can see them (tests/integrators/test_planted_bias.cpp). A harness that
// cannot detect a planted bias is no evidence of unbiasedness. Null in every real render; nothing
// outside the tests sets it, and it is not an option.
#pragma once

namespace rl {

struct PlantedBias {
  // Every shift's jacobian |∂T/∂x| times this, in the resampling weights and in the MIS weights'
  // shifted-back targets alike (a wrong jacobian formula).
  float jacobian_scale = 1;
  // A reused input's target p̂_{←i} scaled by this in its *own* MIS weight only (the other inputs'
  // weights see it unscaled), so the weights no longer sum to one (GRIS eqs. 19-20).
  float own_target_scale = 1;
  // Removes the hybrid shift's invertibility check (pt_path.cpp), the bias of the first review.
  bool skip_hybrid_check = false;
  // pt.reconnection = footprint or pt.roughness_proxy = pdf: the criterion is tested on the base
  // path only (its walk chooses x_k by it) and never re-tested on the offset path (replayed pairs,
  // y_{k-1} -> x_k).
  bool criterion_one_sided = false;
  // ReSTIR DI in an animated scene: tests the history's visibility in this frame's BVH instead of
  // the previous frame's (the approximation before issue 11's fix; -5 to -17% behind a fast occluder).
  bool history_visibility_now = false;
  // ReSTIR GI in an animated scene: the history keeps its cached radiance and position, evaluated in
  // this frame's scene (what a GI without issue 11's replay would do: a switched-off light's ghost).
  bool gi_history_cached = false;
  // Paired spatial reuse (paired_reuse.h): the shift pass rejects partners farther from the camera
  // (a one-sided test: one pixel of each pair shifts, the resampling pass accepts both); or the
  // partner's offset skips the transform's transpose, so a partner's partner is not the pixel (a
  // broken involution).
  bool pairing_one_sided = false;
  bool pairing_broken = false;
  // pt.force_nee_reconnection: the walks force an NEE path's light vertex to be its reconnection
  // vertex, the shifts test the offset path by the ordinary criterion (a one-sided rule).
  bool forced_nee_one_sided = false;
  // pt.roulette = initial: the walk's stored replay densities keep the survival probabilities
  // (as under replayed roulette) while the shifts replay without roulette: a wrong Jacobian.
  bool roulette_in_replay = false;
  // *.rgb_weights: each input's colour weight w_i F(Y_i) / p̂ divides by its own-domain target
  // p̂_i(X_i) instead of p̂(Y_i) in this pixel's domain (reuse_pixel.h's ReuseColor).
  bool color_input_target = false;
  // pt.nee_candidates > 1: the walk's resampled light point is weighted by its source density
  // p(Y) instead of its RIS contribution weight W (as if the choice among the candidates were free).
  bool nee_source_density = false;
  // *.spatial_mis / temporal_mis = asymmetric-ratio: the canonical sample weighted by the symmetric
  // ratio weight's formula instead of 1 - Σ_j m_j (restir/mis.h), so the weights do not sum to one.
  bool ratio_canonical_symmetric = false;
};

}  // namespace rl
