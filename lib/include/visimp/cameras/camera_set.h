// Camera sets: the directions from which visimp looks at a mesh (Zhang & Turk 2002, §4).
//
// Every camera is orthographic and looks at the centre of the mesh's bounding sphere; a
// camera is therefore just a unit direction d (from the centre toward the camera). The
// paper assumes each camera stands for an equal area of the sphere, so the sets here are
// as even as a subdivision allows.
//
//   octahedron level k : the vertices of an octahedron whose faces are split 1→4 k times and
//                        projected to the sphere: 6, 18, 66, 258, 1026, 4098 cameras (k=0..5).
//                        The face hierarchy is kept: locate() finds the leaf face around any
//                        direction with 3 plane tests a level (the 8 root faces are octants).
//   dodecahedron       : its 20 vertices (the image-error views of issue 4).
//   file               : a user list, one "x y z" per line ('#' comments), normalised.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "visimp/core/mesh.h"
#include "visimp/core/vec3.h"

namespace visimp {

struct CameraSet {
  std::string name;              ///< "octahedron-k3", "dodecahedron" or the file it came from
  std::vector<Vec3> directions;  ///< unit vectors from the bounding-sphere centre to each camera

  std::size_t size() const { return directions.size(); }
};

/// The octahedron subdivided `level` times with its face hierarchy. Vertices are unit
/// vectors; leaf faces index them and are oriented counter-clockwise seen from outside.
class SphereTessellation {
 public:
  static constexpr int kMaxLevel = 5;
  /// Throws UsageError unless 0 <= level <= kMaxLevel.
  explicit SphereTessellation(int level);

  int level() const { return static_cast<int>(levels_.size()) - 1; }
  const std::vector<Vec3>& vertices() const { return vertices_; }
  const std::vector<Face>& leaf_faces() const { return levels_.back(); }

  /// Index into leaf_faces() of a face whose spherical triangle contains `direction`
  /// (any non-zero vector). On a shared edge or vertex any of the touching faces may be
  /// returned. Cost: 3 sign tests, then at most 3 plane tests per level.
  std::uint32_t locate(const Vec3& direction) const;

  /// True when `direction` lies inside (or on the border of) leaf face `face`.
  bool contains(std::uint32_t face, const Vec3& direction) const;

 private:
  std::vector<Vec3> vertices_;
  /// levels_[i] holds the faces of level i; the children of face f of level i are faces
  /// 4f..4f+3 of level i+1: the corners at its vertices 0, 1, 2, then the centre.
  std::vector<std::vector<Face>> levels_;
};

/// Number of cameras of octahedron level k: 4^(k+1) + 2.
std::size_t octahedron_camera_count(int level);
CameraSet octahedron_cameras(int level);
/// The camera set every visibility command uses unless told otherwise: Zhang & Turk's 258.
inline constexpr const char* kDefaultCameraSet = "258";
CameraSet dodecahedron_cameras();
/// Throws IoError naming the file and line for unreadable files, bad numbers, zero-length
/// or non-finite directions, or an empty list.
CameraSet read_camera_file(const std::string& path);
/// The same from text in memory; `path` names it in errors.
CameraSet parse_camera_list(const std::string& text, const std::string& path);
/// "258" (a count of an octahedron level), "k3" (a level), "dodecahedron", or a file path.
/// Throws UsageError for a number that is not an octahedron count or a level out of range.
CameraSet camera_set_from_spec(const std::string& spec);

}  // namespace visimp
