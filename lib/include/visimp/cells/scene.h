// Scenes for walkthroughs (walkthrough-LOD paper): a list of objects, each a mesh file placed
// by a 4×4 transform, with an optional name. The file format is JSON (docs/cells.md):
//
//   {"format": "visimp-scene", "version": 1,
//    "objects": [{"name": "bunny_0", "mesh": "bunny.ply",
//                 "transform": [16 numbers, row-major, last row 0 0 0 1]}]}
//
// Mesh paths are relative to the scene file's directory; the same path may be placed many
// times (instances share one read). A mesh file also reads as a scene: its connected
// components are the objects, with identity transforms — or, for a file with more than one
// group (an OBJ's `o`/`g` groups, the nodes of a glTF, 3MF, COLLADA, FBX or X3D scene), its
// groups, named as in the file.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "visimp/core/mesh.h"

namespace visimp {

using Transform = std::array<double, 16>;  ///< row-major 4×4, affine (last row 0 0 0 1)
inline constexpr Transform kIdentity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

Vec3 transform_point(const Transform& t, const Vec3& p);
Transform multiply(const Transform& a, const Transform& b);
/// `mesh` moved by `t`, faces rewound when `t` mirrors (so outward normals stay outward).
Mesh transformed(const Mesh& mesh, const Transform& t);

struct SceneObject {
  std::string name;
  std::size_t mesh = 0;  ///< index into Scene::meshes
  Transform transform = kIdentity;
};

struct Scene {
  std::vector<std::string> mesh_paths;  ///< as written in the file (relative to `directory`)
  std::string directory;                ///< the scene file's directory ("" for a mesh read as a scene)
  std::vector<Mesh> meshes;             ///< one per path, in the file's own coordinates
  std::vector<SceneObject> objects;

  /// Object i's mesh in scene coordinates (its transform applied).
  Mesh object_mesh(std::size_t i) const;
  /// Faces over all objects (instances counted each time).
  std::size_t face_count() const;
};

/// Reads a JSON scene (and every mesh it names) or a mesh file as a scene. Throws IoError
/// naming the file and the problem (the object's index for a bad object).
Scene read_scene(const std::string& path);
/// Parses JSON text; `path` names it in messages and gives the directory meshes are read from.
Scene parse_scene(const std::string& text, const std::string& path);
/// Writes the JSON (objects and mesh paths, not the meshes) atomically.
void write_scene(const Scene& scene, const std::string& path);

/// A statuary park (the paper's test scenes): `objects` meshes picked in turn at random from
/// `meshes` (paths; each scaled so its bounding diagonal is `object_size` · U(0.8, 1.2),
/// stood upright on z = 0 — Y-up inputs rotated to Z-up unless `z_up` says otherwise — and
/// turned about z at random) on distinct spots of a jittered grid over `width` × `depth`.
struct ParkOptions {
  std::size_t objects = 64;
  /// When > 0, overrides `objects`: meshes are drawn until their faces reach this total.
  std::size_t faces = 0;
  double width = 200, depth = 200;
  double object_size = 10;
  std::uint64_t seed = 1;
};
Scene make_park(const std::vector<std::string>& meshes, const std::vector<bool>& z_up, const ParkOptions& options);

}  // namespace visimp
