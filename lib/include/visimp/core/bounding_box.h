// Axis-aligned bounding box and the normalisation that maps a mesh into a unit frame
// (centre at the origin, bounding-box diagonal 1). Quadrics and error units are computed
// in that frame so results do not depend on where or how large the input is.
#pragma once

#include <algorithm>
#include <limits>

#include "visimp/core/mesh.h"

namespace visimp {

struct BoundingBox {
  Vec3 min{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
           std::numeric_limits<double>::infinity()};
  Vec3 max{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
           -std::numeric_limits<double>::infinity()};

  bool empty() const { return !(min.x <= max.x); }
  void extend(const Vec3& p) {  // inline: bounding_box() calls it per vertex of 14M-face meshes
    min = {std::min(min.x, p.x), std::min(min.y, p.y), std::min(min.z, p.z)};
    max = {std::max(max.x, p.x), std::max(max.y, p.y), std::max(max.z, p.z)};
  }
  Vec3 center() const { return empty() ? Vec3{} : (min + max) * 0.5; }
  /// Length of the diagonal; 0 for an empty box or a single point.
  double diagonal() const { return empty() ? 0.0 : norm(max - min); }
};

/// Box of the vertices referenced by faces, or of all vertices if there are no faces.
BoundingBox bounding_box(const Mesh& mesh);

/// p_unit = (p - center) * scale with scale = 1/diagonal (1 for a degenerate box).
struct UnitFrame {
  Vec3 center;
  double scale = 1.0;

  Vec3 to_unit(const Vec3& p) const { return (p - center) * scale; }
  Vec3 from_unit(const Vec3& q) const { return q / scale + center; }
};

UnitFrame unit_frame(const BoundingBox& box);

}  // namespace visimp
