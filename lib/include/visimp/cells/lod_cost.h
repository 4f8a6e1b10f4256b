// The walkthrough-LOD paper's edge-collapse cost (../shared/papers/002_*, §3.1):
//
//   cost(vi, vj) = (1.5 − ni·nj)² · l · (wi + wj)
//
// n the vertex normals, w the depth-variation weights (view_weights.h), l the edge's
// projected length: as seen from the cell centre for an SVMesh, and for an MVMesh the
// largest over the cell (its centre and six corners: l′, "the projected length with respect
// to the cell"). Plugged into visimp's collapse engine as a CollapseCost (simplify.h): the
// placement and legality stay the engine's.
//
// One deviation: weights get a floor of 0.01, so parts the depth image does not weigh (smooth
// or hidden) still collapse shortest and flattest first instead of in arbitrary order.
#pragma once

#include <array>
#include <limits>
#include <vector>

#include "visimp/core/mesh.h"
#include "visimp/simplify/simplify.h"

namespace visimp {

class ProjectedLengthCost final : public CollapseCost {
 public:
  /// `eyes`: the cell centre (SVMesh), or the centre and corners (MVMesh); not empty.
  /// `max_length`: the paper's stop rule Tl as an angle (radians): an edge whose projected
  /// length exceeds it is not collapsed (infinite cost), so collapsing ends once every edge
  /// left is longer. Infinity: no such limit (a face-count target stops the run).
  explicit ProjectedLengthCost(std::vector<Vec3> eyes,
                               double max_length = std::numeric_limits<double>::infinity());
  /// For an MVMesh: l′ over the whole cell, not only its centre and corners. `hexagon` is the
  /// cell's six corners (a horizontal hexagon at eye height); an edge's length is also taken
  /// as |edge| / (distance from its midpoint to the hexagon), the most it can subtend from any
  /// eye in the cell — an object just outside a cell's side is nearer to the side's middle than
  /// to any corner.
  void set_region(const std::array<Vec3, 6>& hexagon);
  double cost(const Edge& edge) const override;
  /// The edge's largest angular length over the eyes, in radians (small-angle).
  double projected_length(const Vec3& a, const Vec3& b) const;

 private:
  std::vector<Vec3> eyes_;
  double max_length_;
  bool has_region_ = false;
  std::array<Vec3, 6> region_{};
};

/// The faces of `object` front-facing to at least one of `eyes` (to the centre alone: an
/// SVMesh's; to the centre and corners: an MVMesh's), simplified to `target_faces` with the
/// paper's cost and `weights` (one per vertex of `object`, or empty for all 1). The result
/// keeps the input's vertex positions where the engine does.
/// `max_length` is the Tl stop rule (radians, see ProjectedLengthCost); with it, a
/// `target_faces` of 1 lets Tl alone stop the run.
/// `region`, when given, is set on the cost (an MVMesh's cell).
Mesh build_lod_mesh(const Mesh& object, const std::vector<Vec3>& eyes, const std::vector<float>& weights,
                    std::size_t target_faces, double max_length = std::numeric_limits<double>::infinity(),
                    const std::array<Vec3, 6>* region = nullptr);
/// Distance from `p` to the horizontal hexagon with these corners (0 on it).
double distance_to_hexagon(const std::array<Vec3, 6>& hexagon, const Vec3& p);

}  // namespace visimp
