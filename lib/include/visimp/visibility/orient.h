// Winding repair by visibility (`visimp orient`): every face wound so its front is the side
// the cameras see (docs/visibility.md "Winding"). A face seen from both sides (a sheet, the
// inside of an open vessel) is left as it is; a face no camera sees takes the winding of its
// surface: outward for a closed one (core/orientation.h), the majority of its seen faces for
// an open one.
#pragma once

#include <cstddef>

#include "visimp/core/mesh.h"
#include "visimp/visibility/visibility.h"

namespace visimp {

struct OrientOptions {
  /// A face counts as seen from both sides when each side's V exceeds this. Range [0, 1).
  double both_sides_threshold = 0.02;
  /// Threads that find the winding patches (0: one per hardware thread); any count gives the
  /// same result.
  unsigned threads = 0;
};

struct OrientResult {
  Mesh mesh;                             ///< the input with some faces reversed (qualities kept)
  std::size_t reversed = 0;              ///< faces turned
  std::size_t seen_from_both_sides = 0;  ///< left as they were
  std::size_t never_seen = 0;            ///< wound like their surface
};

/// `visibility` must come from compute_visibility on `mesh` (face_front / face_back per face).
/// Throws UsageError when it does not match the mesh or the threshold is out of range.
OrientResult orient_by_visibility(const Mesh& mesh, const Visibility& visibility, const OrientOptions& options = {});

}  // namespace visimp
