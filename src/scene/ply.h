// PLY triangle meshes: ascii, binary_little_endian and binary_big_endian.
// Reads vertex x y z, optional nx ny nz, optional u v (also s t, texture_u/texture_v,
// texture_s/texture_t) and face vertex_indices (or vertex_index) lists; polygons with more than
// three vertices are fan-triangulated (quads -> 2 triangles). Other elements and properties are
// skipped.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/math.h"

namespace rl {

struct PlyMesh {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;  // empty or one per vertex
  std::vector<Vec2> uvs;      // empty or one per vertex
  std::vector<uint32_t> indices;  // 3 per triangle
};

// Throws SceneError ("file.ply:LINE: ..." for header/ascii problems, "file.ply: ..." for binary).
PlyMesh read_ply(const std::string& path);

}  // namespace rl
