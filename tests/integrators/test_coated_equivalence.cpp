// Coated diffuse (scene/bsdf_coated.h) under every ReSTIR integrator: ReSTIR PT with each shift,
// ReSTIR DI and ReSTIR GI agree with the path tracer (tests/support/equivalence.h) on a room whose
// floor is half a smooth coat (a delta lobe mixed with the diffuse base: the mixed-BSDF rules of
// walk.h, di_specular, gi_initial) and half a rough one. The walls are diffuse, so ReSTIR GI's
// sample points are (its cached radiance is exact on diffuse points only, restir_gi.cpp).
#include <doctest/doctest.h>

#include <fstream>
#include <string>

#include "equivalence.h"

using namespace rl;
using namespace rl::test;

namespace {

std::string coated_room() {
  const std::string path = std::string(RESTIR_BINARY_DIR) + "/coated-room.pbrt";
  std::ofstream f(path);
  f << R"(LookAt 0 1.3 -2.4   0 0.1 0.7   0 1 0
Camera "perspective" "float fov" 50
Film "rgb" "integer xresolution" 16 "integer yresolution" 16
WorldBegin
LightSource "infinite" "rgb L" [0.3 0.32 0.35]
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [0.9 0.85 0.8] "bool twosided" true
  Shape "trianglemesh" "point3 P" [ -1.8 2 -1.5 1.8 2 -1.5 1.8 2 2 -1.8 2 2 ] "integer indices" [ 0 1 2 0 2 3 ]
AttributeEnd
Material "diffuse" "rgb reflectance" [0.7 0.7 0.7]
Shape "trianglemesh"
  "point3 P" [ -1.8 0 2 -1.8 2 2 1.8 2 2 1.8 0 2  -1.8 0 -1.5 -1.8 2 -1.5 -1.8 2 2 -1.8 0 2 ]
  "integer indices" [ 0 1 2 0 2 3 4 5 6 4 6 7 ]
Material "diffuse" "rgb reflectance" [0.2 0.3 0.65]
Shape "trianglemesh" "point3 P" [ 0.6 0 1.2 0.6 0.9 1.2 1.2 0.9 1.2 1.2 0 1.2 ] "integer indices" [ 0 1 2 0 2 3 ]
Material "coateddiffuse" "rgb reflectance" [0.6 0.25 0.15]
Shape "trianglemesh" "point3 P" [ -1.8 0 -1.5 -1.8 0 2 0 0 2 0 0 -1.5 ] "integer indices" [ 0 1 2 0 2 3 ]
Material "coateddiffuse" "rgb reflectance" [0.15 0.3 0.6] "float roughness" 0.1
Shape "trianglemesh" "point3 P" [ 0 0 -1.5 0 0 2 1.8 0 2 1.8 0 -1.5 ] "integer indices" [ 0 1 2 0 2 3 ]
)";
  return path;
}

// One configuration against the path tracer, at the harness's CI tier (image mean 1 %, blocks 3 %;
// RESTIR_EQUIVALENCE=full: 4x the sequences and the reference, 0.5 % / 2 %). Lean: ~30 s on two
// cores for the five configurations.
void certify(const std::string& label, const std::string& path, const Scene& scene, const Options& o) {
  const Certification c = certification(restir::ReuseMis::pairwise, 400, 400, 16384);
  certify_one(label, path, scene, o, c);
}

}  // namespace

TEST_SUITE("slow_equivalence_coated") {
  TEST_CASE("coated diffuse: ReSTIR PT (every shift), DI and GI are equivalent to the path tracer") {
    const std::string path = coated_room();
    Scene scene = load_scene(path);
    for (const char* shift : {"reconnection", "random-replay", "hybrid"}) {
      Options o = pt_certification_options(scene);
      set_option(o, "pt.shift", shift);
      certify(std::string("restir-pt ") + shift, path, scene, o);
    }
    Options di = options_for(scene, {"integrator=restir-di", "render.spp=1", "render.frames=8", "render.sample_pattern=center",
                                     "film.width=16", "film.height=16", "di.light_candidates=4", "di.bsdf_candidates=2",
                                     "di.spatial_neighbors=4", "di.spatial_radius=4"});
    certify("restir-di", path, scene, di);
    Options gi = options_for(scene, {"integrator=restir-gi", "render.spp=1", "render.frames=8", "render.sample_pattern=center",
                                     "film.width=16", "film.height=16", "path.max_depth=3", "gi.spatial_neighbors=4",
                                     "gi.spatial_radius=4"});
    certify("restir-gi", path, scene, gi);
  }
}
