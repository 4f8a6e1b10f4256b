// The hexagonal navigation cells of the walkthrough-LOD paper (../shared/papers/002_*, §3.1
// "Hexagonal spatial subdivision"): the x-y plane tiled by equal regular hexagons, the
// viewer at a fixed eye height.
//
// Hexagons are pointy-topped with circumradius `size` (corner to centre), in axial
// coordinates (q, r): centre = origin + size·(√3·(q + r/2), 3/2·r). Point location is a
// partition: every point of the plane belongs to exactly one cell, the one with the nearest
// centre (a regular hexagonal tiling is the Voronoi diagram of its centres), a tie on a
// shared edge or corner going to the smaller (r, q).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "visimp/core/vec3.h"

namespace visimp {

struct HexCell {
  int q = 0, r = 0;
  bool operator==(const HexCell& o) const { return q == o.q && r == o.r; }
  bool operator!=(const HexCell& o) const { return !(*this == o); }
};

class HexGrid {
 public:
  /// Throws OptionError unless size > 0 and finite, and the eye height is finite.
  HexGrid(double size, double eye_height = 1.7, double origin_x = 0, double origin_y = 0);

  double size() const { return size_; }
  double eye_height() const { return eye_height_; }

  /// The cell holding (x, y): the nearest centre, ties to the smaller (r, q), so neighbours
  /// never both claim a point and no point is left out, in floating point too.
  HexCell cell_of(double x, double y) const;
  /// Centre of a cell in the plane, and at eye height.
  std::array<double, 2> center(const HexCell& c) const;
  Vec3 eye_at_center(const HexCell& c) const;
  /// The six corners at eye height, counter-clockwise from the top.
  std::array<Vec3, 6> corners(const HexCell& c) const;
  /// The six neighbours, counter-clockwise from the east.
  std::array<HexCell, 6> neighbours(const HexCell& c) const;
  /// Whether (x, y) lies in the closed hexagon of `c`.
  bool contains(const HexCell& c, double x, double y) const;
  /// The cells whose hexagons meet the rectangle [x0, x1] × [y0, y1].
  std::vector<HexCell> cells_covering(double x0, double y0, double x1, double y1) const;

 private:
  double size_, eye_height_, origin_x_, origin_y_;
};

}  // namespace visimp
