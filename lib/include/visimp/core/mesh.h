// The triangle mesh every visimp stage reads and writes: an indexed face set with optional
// per-vertex and per-face scalars ("quality", as MeshLab calls them).
//
// Contract: faces index into positions; a face may be degenerate (zero area, or even a
// repeated index) and a vertex may be unreferenced — visimp keeps what the input had and
// reports it (see validate.h and mesh_stats.h) instead of silently dropping it.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "visimp/core/vec3.h"

namespace visimp {

using VertexIndex = std::uint32_t;
using Face = std::array<VertexIndex, 3>;

struct Mesh {
  std::vector<Vec3> positions;
  std::vector<Face> faces;
  /// Empty, or one value per vertex (PLY vertex property `quality`).
  std::vector<float> vertex_quality;
  /// Empty, or one value per face (PLY face property `quality`; visimp stores V(t) here).
  std::vector<float> face_quality;

  std::size_t num_vertices() const { return positions.size(); }
  std::size_t num_faces() const { return faces.size(); }
  bool has_vertex_quality() const { return !vertex_quality.empty(); }
  bool has_face_quality() const { return !face_quality.empty(); }
};

/// Twice the face's area vector (cross product of two edges); zero for a degenerate face.
inline Vec3 face_normal_unnormalized(const Mesh& mesh, const Face& f) {
  const Vec3& a = mesh.positions[f[0]];
  return cross(mesh.positions[f[1]] - a, mesh.positions[f[2]] - a);
}

}  // namespace visimp
