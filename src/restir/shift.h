// Geometry of shift mappings, as pure functions (no scene types).
#pragma once
#include "core/math.h"

namespace rl::restir {

// Jacobian |∂ω_y/∂ω_x| of the reconnection shift: the base path leaves x_prev in direction ω_x and
// reaches x_k (normal n_k); the offset path leaves y_prev toward the same x_k in direction ω_y.
// Both directions are measured in solid angle at their origins (Ouyang et al. 2021, ReSTIR GI
// eq. 11; Lin et al. 2022 eq. 52):
//   |cos φ_y| / |cos φ_x| · |x_k − x_prev|² / |x_k − y_prev|²,
// φ the angles at x_k between n_k and the segments to y_prev and x_prev. 0 when degenerate.
//
// The moved form: between two frames x_k is carried by a rigid motion from x_k (normal n_k, seen
// from x_prev) to y_k (normal m_k, seen from y_prev). A rigid motion keeps area, so the Jacobian
// still passes through dA at x_k: |∂ω_y/∂ω_x| = (|cos φ_y| / |y_k − y_prev|²) · (|x_k − x_prev|² / |cos φ_x|).
RESTIR_HD inline float moved_reconnection_jacobian(Vec3 x_prev, Vec3 x_k, Vec3 n_k, Vec3 y_prev, Vec3 y_k, Vec3 m_k) {
  const Vec3 to_x = x_prev - x_k, to_y = y_prev - y_k;
  const float dx2 = length_squared(to_x), dy2 = length_squared(to_y);
  if (!(dx2 > 0) || !(dy2 > 0)) return 0;
  const float cos_x = std::fabs(dot(n_k, to_x)) / std::sqrt(dx2);
  const float cos_y = std::fabs(dot(m_k, to_y)) / std::sqrt(dy2);
  if (!(cos_x > 0)) return 0;
  return (cos_y / cos_x) * (dx2 / dy2);
}

RESTIR_HD inline float reconnection_jacobian(Vec3 x_prev, Vec3 y_prev, Vec3 x_k, Vec3 n_k) {
  return moved_reconnection_jacobian(x_prev, x_k, n_k, y_prev, x_k, n_k);
}

// One path's half of that Jacobian: |cos φ| / |x_k − prev|², the factor turning solid angle at
// prev into area at x_k (0 when degenerate or not finite). The Jacobian is the offset path's over
// the base path's, so a sample that keeps its own (ReSTIR PT's rc_geometry) need not keep prev.
RESTIR_HD inline float reconnection_geometry(Vec3 prev, Vec3 x_k, Vec3 n_k) {
  const Vec3 to = prev - x_k;
  const float d2 = length_squared(to);
  if (!(d2 > 0)) return 0;
  const float g = std::fabs(dot(n_k, to)) / std::sqrt(d2) / d2;
  return std::isfinite(g) ? g : 0.0f;
}

// reconnection_jacobian from the two paths' halves: g_y / g_x (0 when either is 0).
RESTIR_HD inline float reconnection_jacobian_from(float g_x, float g_y) { return g_x > 0 && g_y > 0 ? g_y / g_x : 0.0f; }

}  // namespace rl::restir
