#include "scene/scene_view.h"

namespace rl {

SceneViewData::SceneViewData(const Scene& scene) {
  meshes.reserve(scene.meshes.size());
  for (const TriangleMesh& m : scene.meshes) {
    MeshView v;
    v.positions = m.positions.data();
    v.normals = m.normals.empty() ? nullptr : m.normals.data();
    v.uvs = m.uvs.empty() ? nullptr : m.uvs.data();
    v.indices = m.indices.data();
    v.vertex_count = uint32_t(m.positions.size());
    v.triangle_count = uint32_t(m.triangle_count());
    v.material = m.material;
    v.flip_normal = m.flip_normal;
    v.animation = m.animation;
    meshes.push_back(v);
  }
  for (const Sphere& s : scene.spheres) spheres.push_back({s.center, s.radius, s.material, s.flip_normal, s.animation});
  for (const Material& m : scene.materials) materials.push_back(m);
  for (const Texture& t : scene.textures) textures.push_back({t, image_view(t.image)});
}

}  // namespace rl
