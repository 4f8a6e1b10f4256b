// analyze(mesh): counts what `visimp info` reports and what the simplifier must respect:
// components, boundary and non-manifold edges, non-manifold vertices, misoriented edges,
// degenerate and duplicate faces. Linear time but for small sorts: half-edges and faces are laid
// out grouped by their lowest vertex, and each group sorted. Face indices must be below the
// vertex count (every reader and the Python module check them).
#pragma once

#include <algorithm>

#include <cstddef>

#include "visimp/core/bounding_box.h"
#include "visimp/core/mesh.h"

namespace visimp {

struct MeshStats {
  std::size_t vertices = 0;
  std::size_t faces = 0;
  std::size_t isolated_vertices = 0;      ///< referenced by no face
  std::size_t components = 0;             ///< connected components of faces (via shared vertices)
  std::size_t edges = 0;                  ///< distinct undirected edges
  std::size_t boundary_edges = 0;         ///< edges with exactly one face
  std::size_t non_manifold_edges = 0;     ///< edges with three or more faces
  std::size_t misoriented_edges = 0;      ///< two-face edges traversed in the same direction by both
  std::size_t non_manifold_vertices = 0;  ///< vertices whose faces form more than one fan
  std::size_t degenerate_faces = 0;       ///< zero area (collinear or repeated vertices)
  std::size_t duplicate_faces = 0;        ///< faces with the same vertex set as an earlier face
  double area = 0;                        ///< total surface area, input units
  BoundingBox bbox;

  /// Closed 2-manifold: no boundary, no non-manifold edge or vertex.
  bool closed_manifold() const {
    return faces > 0 && boundary_edges == 0 && non_manifold_edges == 0 && non_manifold_vertices == 0;
  }
};

MeshStats analyze(const Mesh& mesh);

/// analyze(mesh).area alone: the areas of the non-degenerate faces summed in face order.
double surface_area(const Mesh& mesh);

/// True when the face has a repeated vertex index or (numerically) zero area relative to
/// its longest edge: such a face has no normal and contributes no plane anywhere in visimp.
bool is_degenerate(const Mesh& mesh, const Face& f);
/// The same for a face over a bare position array (a refined or re-wound copy).
bool is_degenerate(const std::vector<Vec3>& positions, const Face& f);
/// The same test on three corner positions.
bool is_degenerate_triangle(const Vec3& a, const Vec3& b, const Vec3& c);
/// The same test for a caller that already has |cross(b - a, c - a)| (twice the area): the
/// collapse filter computes it for the normal check anyway.
inline bool is_degenerate_triangle(const Vec3& a, const Vec3& b, const Vec3& c, double cross_length) {
  const double longest2 = std::max({squared_norm(b - a), squared_norm(c - b), squared_norm(a - c)});
  // |cross| = 2·area; relative to the longest edge squared this is ~sin of the smallest
  // angle. Below 1e-13 the normal is rounding noise in double.
  return !(cross_length > 1e-13 * longest2);
}

}  // namespace visimp
