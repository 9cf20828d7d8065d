#include "study/masks.h"

#include "core/parallel.h"
#include "backends/cpu/accel.h"
#include "scene/bsdf.h"
#include "scene/camera.h"

namespace rl::study {

std::vector<uint8_t> reflective_mask(const Scene& scene, const Options& o, const CameraKey& camera, float max_roughness) {
  const int w = o.film.width, h = o.film.height;
  std::vector<uint8_t> mask(size_t(w) * size_t(h), 0);
  Accel accel(scene);
  PerspectiveCamera cam(camera, w, h);
  parallel_for(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const Ray ray = cam.generate_ray({float(x) + 0.5f, float(y) + 0.5f});
      Hit hit;
      if (!accel.intersect(ray, hit)) continue;
      const Material& m = scene.materials[size_t(accel.interaction(ray, hit).material)];
      mask[size_t(y) * size_t(w) + size_t(x)] = bsdf_roughness(make_bsdf(m, m.reflectance)) <= max_roughness ? 1 : 0;
    }
  });
  return mask;
}

}  // namespace rl::study
