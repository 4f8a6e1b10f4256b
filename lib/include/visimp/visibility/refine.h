// Refinement by edge length (Zhang & Turk 2002, §4): "we add vertices to the middle of any
// edge that is longer than l. For each triangle, based on the number of new vertices added
// to its edges, we divide it into sub-triangles. This process is repeated until all mesh
// edges are shorter than l." Large faces would otherwise break the assumption that F(t, v)
// is constant over a face.
//
// The result is conforming (a split edge is split for both of its faces, so rendering sees
// no cracks), keeps orientation, and every sub-face remembers its input face.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "visimp/core/mesh.h"

namespace visimp {

struct RefinedMesh {
  Mesh mesh;                              ///< positions and faces only
  std::vector<std::uint32_t> input_face;  ///< per sub-face: the input face it lies in
  int rounds = 0;                         ///< midpoint rounds that were needed
};

/// l from the paper's rule: a pixel of the R×R view of the bounding sphere (radius r) is
/// s = 2r/R wide; a face seen at the worst angle (cos = worst_view_cosine, 0.25 ≈ 75.5°) is
/// foreshortened by that cosine, so edges up to s / worst_view_cosine still project to
/// about one pixel there. See docs/visibility.md.
double refinement_edge_length(double bounding_radius, int resolution, double worst_view_cosine);

/// True when some edge is longer than max_edge (refine_long_edges would split it).
bool has_edge_longer_than(const Mesh& mesh, double max_edge);

/// Splits until no edge is longer than max_edge. Returns nothing when no edge is longer
/// (the common case for scans: the step is skipped, nothing is copied). Throws UsageError
/// when the result would exceed max_faces faces.
std::optional<RefinedMesh> refine_long_edges(const Mesh& mesh, double max_edge, std::size_t max_faces);
/// The same, taking the mesh's positions and faces over instead of copying them.
std::optional<RefinedMesh> refine_long_edges(Mesh&& mesh, double max_edge, std::size_t max_faces);

}  // namespace visimp
