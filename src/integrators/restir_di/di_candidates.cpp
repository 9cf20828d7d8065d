#include "integrators/restir_di/di_candidates.h"

#include "core/widest.h"
#include "integrators/restir_di/restir_di_pixel.h"

namespace rl {

// The batch of light candidates on this machine's widest vectors (core/widest.h): AVX2's 8 lanes
// where the CPU has them, the baseline SSE2's 4 elsewhere; the same floats either way.
RL_WIDEST uint32_t di_eval_light_candidates_host(const LightsView& lights, const GSurface& s, Vec3 wo_l, bool bsdf_pdfs,
                                                 DiCandidateBatch& b) {
  return di_eval_light_candidates(lights, s, wo_l, bsdf_pdfs, b);
}

}  // namespace rl
