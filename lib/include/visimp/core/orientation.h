// Consistent orientation patches: faces joined across manifold edges (exactly two faces),
// each wound consistently with its neighbours, and every patch turned so it encloses
// positive signed volume about the bounding-box centre. The result depends only on the
// surface, not on how its faces happen to be wound: reversing any subset of faces of the
// input gives the same canonical faces (visibility renders those, so V cannot depend on
// winding; docs/visibility.md "Winding").
//
// A patch is *closed* when every edge of its faces has exactly two faces, both in the
// patch, and its winding could be made consistent (not a Möbius-like surface). A closed
// patch turned to positive volume is wound outward: a ray from outside that reaches the
// back of one of its faces has first crossed one of its front faces.
#pragma once

#include <cstdint>
#include <vector>

#include "visimp/core/mesh.h"

namespace visimp {

struct OrientationPatches {
  std::vector<std::uint32_t> patch_of_face;  ///< per face: its patch, 0..patches-1
  std::vector<std::uint8_t> reversed;        ///< per face: 1 when the canonical winding reverses the input's
  std::vector<std::uint8_t> closed;          ///< per patch: closed, orientable surface (see above)
  std::vector<double> signed_volume;         ///< per patch, in canonical winding (≥ 0 up to rounding)
  std::size_t patches() const { return closed.size(); }
};

/// Linear time (edges bucketed by their lower vertex). Faces with a repeated index join no
/// patch (each is a patch of its own, never closed). `threads` (0 = one per hardware thread)
/// share the edge matching; the result does not depend on it.
OrientationPatches orientation_patches(const Mesh& mesh, unsigned threads = 0);

/// The face wound as `reversed` says, rotated so its smallest vertex index comes first:
/// one canonical form per triangle and side, whatever the input's rotation.
Face canonical_face(const Face& face, bool reversed);

}  // namespace visimp
