#include "scene/scene.h"

namespace rl {

Bounds3 Scene::bounds() const {
  Bounds3 b;
  for (const TriangleMesh& m : meshes)
    for (const Vec3& p : m.positions) b.extend(p);
  for (const Sphere& s : spheres) {
    b.extend(s.center - Vec3(s.radius));
    b.extend(s.center + Vec3(s.radius));
  }
  return b;
}

size_t Scene::triangle_count() const {
  size_t n = 0;
  for (const TriangleMesh& m : meshes) n += m.triangle_count();
  return n;
}

}  // namespace rl
