// Export of a parsed Scene to a Mitsuba 3 scene (scene.xml + binary PLY meshes + EXR images), so
// that an independent renderer can serve as a second reference for the path tracer
// (scripts/validate-mitsuba.sh). Everything is written from the *parsed* scene, i.e. with the
// meanings restir-lab gives each quantity; where Mitsuba 3 cannot express one exactly the
// exporter approximates it and returns a note saying what differs.
//
// Mapping (restir-lab -> Mitsuba 3):
// - diffuse, rough conductor: the `twosided` wrapper (restir-lab shades both sides, Mitsuba's
//   BSDFs are black from below); dielectrics stay one BSDF (inside/outside by the normal in both).
// - GGX alpha: restir-lab stores the alpha after pbrt-v4's remapping, which is Mitsuba's `alpha`
//   directly; max(alpha) < 1e-3 is smooth in restir-lab, so it becomes `conductor`/`dielectric`.
//   Mitsuba's Smith G is the separable G1(wo) G1(wi), restir-lab's (pbrt-v4's) height-correlated:
//   rough lobes differ slightly at grazing angles, by design of the two renderers.
// - coated diffuse: `plastic` (smooth coat) or `roughplastic` (ggx, alpha, int_ior = eta,
//   ext_ior = 1), both with nonlinear = true (bsdf_coated.h's model), in `twosided`. Mitsuba's
//   plastic takes Fdr from a polynomial fit, roughplastic tabulates T and Fdr with the separable G:
//   small differences, largest at grazing angles; an anisotropic coat goes out with the mean alpha.
// - conductor "reflectance" r: eta = 1, k = 2 sqrt(r / (1 - r)) (restir-lab's exact conversion).
// - meshes: world space, indices wound so that Mitsuba's face normal is triangle_normal();
//   `face_normals` when the mesh has no shading normals (Mitsuba would smooth them otherwise).
// - emission: Mitsuba's `area` is one-sided; a two-sided emitter becomes two copies offset by a
//   tiny epsilon along the normal, facing away from each other.
// - environment: baked into a world-space equirect EXR in Mitsuba's own convention (to_world =
//   identity) by evaluating restir-lab's lookup at Mitsuba's texel positions, which covers both
//   the equirect and the equal-area octahedral maps and any orientation; Mitsuba interpolates
//   bilinearly where restir-lab looks up the nearest texel (a slight blur, same integral).
// - point, spot, distant lights: Mitsuba's `point`, `spot` and `directional` (irradiance = L,
//   direction = the one the light travels). A spot's cone: cutoff_angle = coneangle, beam_width =
//   coneangle - conedeltaangle, full intensity within beam_width in both. Between the two the
//   renderers differ by design: Mitsuba's falloff is linear in the angle, (cutoff - theta) /
//   (cutoff - beam_width), pbrt-v4's (and restir-lab's) is smoothstep in cos theta; the export notes
//   it for a spot with a falloff band (compare inside the full-intensity cone, or account for it).
// - camera: to_world = world_from_camera * Scale(-1, 1, 1) (pbrt's camera space is left-handed,
//   Mitsuba's image x runs along -x), fov_axis "smaller" (pbrt-v4's fov spans the shorter axis).
// - max depth: restir-lab counts bounces (1 = direct lighting), Mitsuba counts path vertices
//   after the camera (2 = direct lighting): Mitsuba max_depth = path.max_depth + 1.
#pragma once
#include <string>
#include <vector>

#include "scene/scene.h"

namespace rl {

struct MitsubaExportSettings {
  int width = 640, height = 360;  // film.width / film.height
  int spp = 64;                   // render.spp (Mitsuba's sampler sample_count)
  int max_depth = 5;              // restir-lab path.max_depth (bounces)
  std::string filter = "box";     // film.filter: box | triangle | gaussian
  float filter_radius = 0.5f;     // film.filter_radius (pixels)
  CameraKey camera;               // the frame's camera
};

// Writes DIR/scene.xml, DIR/meshes/*.ply, DIR/textures/*.exr and DIR/envmap.exr (creating DIR).
// Returns one line per approximation made. Throws IoError or ImageError (the files written
// through image/image_io.h) on I/O errors, SceneError for a singular camera.
std::vector<std::string> export_mitsuba(const Scene& scene, const MitsubaExportSettings& settings,
                                        const std::string& dir);

}  // namespace rl
