// ReSTIR DI and ReSTIR PT under spot and distant lights agree with the path tracer (the harness of
// tests/support/equivalence.h). A delta light's sample is a fixed point or direction whatever the
// receiver: the candidates' densities are counting measures, a reused spot sample must be
// re-evaluated with its falloff toward the new receiver, a distant light's shadow ray is unbounded,
// and in ReSTIR PT a reconnection to the light vertex has Jacobian 1 (as the environment's). Any
// of these done wrong shows up as a bias against the path tracer on this scene: the spot's band
// and cone edge fall across the floor, a box shadows both lights, and a glossy block reflects them.
// Checked once by hand: with a reconnection to the spot keeping its on-axis intensity (falloff not
// re-evaluated for the shifted receiver) PT comes out +1.0 % (5 standard errors) and fails.
#include <doctest/doctest.h>

#include <fstream>

#include "equivalence.h"

using namespace rl;
using namespace rl::test;

namespace {

std::string delta_lights_scene() {
  const std::string path = std::string(RESTIR_BINARY_DIR) + "/delta-lights.pbrt";
  std::ofstream(path) << R"(LookAt 0 3 -5  0 0.3 0.5  0 1 0
Camera "perspective" "float fov" 50
Film "rgb" "integer xresolution" 16 "integer yresolution" 16
WorldBegin
LightSource "spot" "point3 from" [-1.2 2.5 -0.8] "point3 to" [0.2 0 0.6] "rgb I" [14 12 10]
  "float coneangle" 35 "float conedeltaangle" 15
LightSource "distant" "point3 from" [1 2 -0.8] "point3 to" [0 0 0] "rgb L" [0.9 1.0 1.2]
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [4 4 4]
  Shape "trianglemesh" "point3 P" [ 1.5 2.0 1.5  2.0 2.0 1.5  2.0 2.0 2.0  1.5 2.0 2.0 ] "integer indices" [ 0 1 2 0 2 3 ]
AttributeEnd
Material "diffuse" "rgb reflectance" [0.6 0.6 0.6]
Shape "trianglemesh" "point3 P" [ -3 0 -3 -3 0 3 3 0 3 3 0 -3 ] "integer indices" [ 0 1 2 0 2 3 ]
Shape "trianglemesh" "point3 P" [ -3 0 2.2 -3 2.5 2.2 3 2.5 2.2 3 0 2.2 ] "integer indices" [ 0 1 2 0 2 3 ]
Material "diffuse" "rgb reflectance" [0.7 0.4 0.2]
Shape "trianglemesh" "point3 P" [ -0.3 0 0  0.3 0 0  0.3 0.8 0  -0.3 0.8 0 ] "integer indices" [ 0 1 2 0 2 3 ]
Material "conductor" "float roughness" 0.3
Shape "trianglemesh" "point3 P" [ 0.8 0 1.0  1.6 0 1.0  1.6 0.9 1.4  0.8 0.9 1.4 ] "integer indices" [ 0 1 2 0 2 3 ]
)";
  return path;
}

void certify(const std::string& label, const std::string& path, const Scene& scene, const Options& o, int runs, int reference_spp) {
  const Certification c = certification(restir::ReuseMis::pairwise, runs, runs, reference_spp);
  certify_one(label, path, scene, o, c);
}

}  // namespace

TEST_SUITE("slow_equivalence_lights") {
  TEST_CASE("ReSTIR DI with spot and distant lights is equivalent to direct lighting") {
    const std::string path = delta_lights_scene();
    const Scene scene = load_scene(path);
    const Options o = options_for(scene, {"integrator=restir-di", "render.spp=1", "render.frames=8", "render.sample_pattern=center",
                                          "film.width=16", "film.height=16", "di.light_candidates=4", "di.bsdf_candidates=1",
                                          "di.spatial_neighbors=6", "di.spatial_radius=4"});
    certify("restir-di spot + distant", path, scene, o, 400, 65536);
  }

  TEST_CASE("ReSTIR PT (reconnection, hybrid) with spot and distant lights is equivalent to the path tracer") {
    const std::string path = delta_lights_scene();
    const Scene scene = load_scene(path);
    for (const char* shift : {"reconnection", "hybrid"}) {
      Options o = pt_certification_options(scene);
      set_option(o, "pt.shift", shift);
      certify(std::string("restir-pt spot + distant ") + shift, path, scene, o, 240, 65536);
    }
  }
}
