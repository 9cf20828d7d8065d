// Scene loading: pbrt-v4 (a documented subset), OBJ+MTL, glTF 2.0 and PLY files -> rl::Scene.
//
// Every problem is a SceneError whose what() is one line "FILE:LINE: message" (or "FILE: message"
// where no line applies). A failed load never returns a partially filled scene.
#pragma once
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/math.h"
#include "scene/scene.h"

namespace rl {

// A scene file (or a file it names: mesh, texture, animation, camera path) that cannot be loaded.
class SceneError : public std::runtime_error {
 public:
  // line <= 0: no line ("FILE: message").
  SceneError(const std::string& file, int line, const std::string& message);
  // Not located yet: what() is the message as given. A caller that knows the file wraps it
  // (detail::located passes only located errors through as they are).
  explicit SceneError(const std::string& message);
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& message() const { return message_; }
  bool located() const { return located_; }

 private:
  std::string file_;
  int line_;
  std::string message_;
  bool located_ = true;
};

// Loads a whole scene, dispatching on the (case-insensitive) extension:
//   .pbrt           pbrt-v4 subset (see pbrt_parser.cpp for the list of directives)
//   .obj            OBJ + MTL, default camera (see default_camera())
//   .gltf / .glb    glTF 2.0, first camera node or the default camera
//   .ply            one triangle mesh with the default material and the default camera
// Throws SceneError.
Scene load_scene(const std::string& path);

// pbrt-v4 scene file (also reachable through load_scene).
Scene load_pbrt(const std::string& path);

// The camera used when a file has none (OBJ, PLY, glTF without a camera node): it looks at the
// bounds' centre from +z, at a distance of 1.5x the bounding-sphere radius, up = +y, fov 45.
// OBJ and glTF are right-handed; pbrt's camera space is left-handed, so the key mirrors camera x
// (camera_from_world = Scale(-1,1,1) * LookAt) so that world +x appears on the image's right,
// as in the usual right-handed viewers (Blender, glTF viewers).
CameraKey default_camera(const Bounds3& bounds);

namespace detail {

// True for a SceneError that names its file: a caller that adds file:line to the errors it
// catches lets such an error pass as it is.
bool located(const std::exception& e);

// Builds a world-space triangle mesh from object-space data with pbrt-v4's orientation rules
// (Triangle::InteractionFromIntersection): the geometric normal is
// normalize(cross(p0-p2, p1-p2)) (= cross(p1-p0, p2-p0)), negated if reverse_orientation XOR
// world_from_object swaps handedness; with shading normals N, it is then flipped to agree with
// the (interpolated) N. A single per-mesh flip cannot express a per-triangle decision, so the
// mesh gets flip_normal = reverse_orientation XOR swaps-handedness and each triangle whose
// pbrt normal disagrees with that flag has its winding swapped (i1 <-> i2), which leaves the
// renderer's resolved normal equal to pbrt's n. Normals: inverse transpose, normalized; with
// reverse_orientation N is negated, as pbrt-v4 does. Throws an unlocated SceneError on bad
// indices or mismatched array sizes (callers add file:line).
TriangleMesh make_world_mesh(const std::vector<Vec3>& p, const std::vector<Vec3>& n, const std::vector<Vec2>& uv,
                             const std::vector<uint32_t>& indices, const Mat4& world_from_object,
                             bool reverse_orientation);

// The pbrt parser proper (load_pbrt = parse_pbrt + validate_scene + the no-light warning).
Scene parse_pbrt(const std::string& path);

// Applies a further transform to an already world-space mesh (object instancing).
void transform_mesh(TriangleMesh& mesh, const Mat4& xf);

// Reads an image through the image I/O module; rethrows its errors as SceneError(file, line).
Image read_image_for(const std::string& image_path, const std::string& file, int line);

// Options for importing an OBJ/glTF file.
struct MeshImport {
  Mat4 world_from_object;
  bool reverse_orientation = false;
  // true: create materials (and textures, emission) from the file into the scene;
  // false: every mesh gets `material` and `emission` (pbrt "objmesh"/"gltfmesh" shapes).
  bool use_file_materials = true;
  int material = 0;
  std::optional<AreaEmission> emission;
  std::string error_file;  // where to report errors that are not inside the mesh file
  int error_line = 0;
};
// Append the file's triangles to `out`; materials/textures (if used) go into `scene`.
// glTF: a camera node, if any and if `camera` is non-null, is stored there.
void import_obj(const std::string& path, const MeshImport& opt, Scene& scene, std::vector<TriangleMesh>& out);
void import_gltf(const std::string& path, const MeshImport& opt, Scene& scene, std::vector<TriangleMesh>& out,
                 std::optional<CameraKey>* camera);

}  // namespace detail
}  // namespace rl
