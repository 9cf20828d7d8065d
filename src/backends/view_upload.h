// Copies of the scene's, the lights' and a BVH's views into a Store's memory: every array a view
// points to handed to store.upload(pointer, count) or store.upload(vector), which returns where the
// copy lives, and the copy's pointers replaced by those. With cuda::DeviceStore that is device
// memory (the CUDA backend); with HostStore the host's own arrays (the host twin of a backend).
#pragma once
#include <memory>
#include <vector>

#include "backends/bvh.h"
#include "scene/lights_view.h"
#include "scene/scene_view.h"

namespace rl {

// A Store over host memory: arrays stay where they are; temporaries (vectors) are kept alive.
class HostStore {
 public:
  void clear() { owned_.clear(); }
  template <class T>
  const T* upload(const T* host, size_t n) {
    return host && n ? host : nullptr;
  }
  template <class T>
  const T* upload(const std::vector<T>& v) {
    if (v.empty()) return nullptr;
    auto copy = std::make_shared<std::vector<T>>(v);
    owned_.push_back(copy);
    return copy->data();
  }

 private:
  std::vector<std::shared_ptr<const void>> owned_;
};

template <class Store>
SceneView store_scene_view(Store& store, const SceneView& h) {
  std::vector<MeshView> meshes(h.meshes, h.meshes + h.mesh_count);
  for (MeshView& m : meshes) {
    m.positions = store.upload(m.positions, m.vertex_count);
    m.normals = store.upload(m.normals, m.vertex_count);
    m.uvs = store.upload(m.uvs, m.vertex_count);
    m.indices = store.upload(m.indices, size_t(m.triangle_count) * 3);
  }
  std::vector<TextureView> textures(h.textures, h.textures + h.texture_count);
  for (TextureView& t : textures)
    t.image.pixels = store.upload(t.image.pixels, t.image.empty() ? 0 : size_t(t.image.width) * size_t(t.image.height));
  SceneView d = h;
  d.meshes = store.upload(meshes);
  d.spheres = store.upload(h.spheres, h.sphere_count);
  d.materials = store.upload(h.materials, h.material_count);
  d.textures = store.upload(textures);
  return d;
}

// lights_view.h's recipe: each array copied, the view's pointers replaced.
template <class Store>
LightsView store_lights_view(Store& store, const LightsView& h) {
  LightsView d = h;
  d.emitters = store.upload(h.emitters, h.num_emitters);
  d.selection.bins = store.upload(h.selection.bins, h.selection.size);
  d.selection.pmfs = store.upload(h.selection.pmfs, h.selection.size);
  d.mesh_first = store.upload(h.mesh_first, h.num_meshes);
  d.sphere_index = store.upload(h.sphere_index, h.num_spheres);
  d.env_texels = store.upload(h.env_texels, h.env_texels ? size_t(h.env_width) * size_t(h.env_height) : 0);
  d.env_rows.bins = store.upload(h.env_rows.bins, h.env_rows.size);
  d.env_rows.pmfs = store.upload(h.env_rows.pmfs, h.env_rows.size);
  d.env_col_bins = store.upload(h.env_col_bins, h.num_env_col_entries);
  d.env_col_pmfs = store.upload(h.env_col_pmfs, h.num_env_col_entries);
  d.env_col_offsets = store.upload(h.env_col_offsets, h.num_env_col_offsets);
  return d;
}

template <class Store>
BvhView store_bvh_view(Store& store, const Bvh& bvh) {
  return BvhView{store.upload(bvh.nodes), store.upload(bvh.wide_nodes), store.upload(bvh.primitives), bvh.node_count(),
                 uint32_t(bvh.primitives.size()), bvh.sphere_geom};
}

}  // namespace rl
