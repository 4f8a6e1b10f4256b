// Certified Hausdorff distance: lower and upper bounds around the true symmetric Hausdorff
// distance between two triangle meshes, at most a requested tolerance apart. Uses CGAL's
// bounded-error Hausdorff distance (Krayer, Haxhimusa & Wimmer's branch-and-bound on the
// triangles), which returns an estimate within `error_bound` of the true value.
#pragma once

#include "visimp/core/mesh.h"

namespace visimp {

struct HausdorffBounds {
  double lower = 0;     ///< the true symmetric Hausdorff distance is >= lower
  double upper = 0;     ///< ... and <= upper (input units)
  double estimate = 0;  ///< CGAL's value, within the tolerance of the truth
  double seconds = 0;
};

/// `tolerance` in input units (> 0). `known_lower` (e.g. a sampled Hausdorff distance, which
/// can only underestimate) tightens the lower bound. Degenerate faces are ignored. Throws
/// InvalidMeshError if a mesh has no non-degenerate face.
HausdorffBounds bounded_hausdorff(const Mesh& a, const Mesh& b, double tolerance, double known_lower = 0);

}  // namespace visimp
