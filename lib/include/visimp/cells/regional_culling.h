// Regional conservative back-face culling (walkthrough-LOD paper §3.1): a face that turns its
// back to all six corners of a navigation cell turns it to every eye in the cell, since
// "front-facing from e" is linear in e (n·(e − p) > 0) and the cell is the corners' convex
// hull. Such faces can be dropped for the whole cell.
//
// The paper tests against the face's centre; any point of the face's plane gives the same
// sign, so the face's first vertex is used (exact for degenerate faces too, whose zero
// normal makes them never back-facing: they are kept).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "visimp/core/mesh.h"

namespace visimp {

/// True when face f of `mesh` is back-facing (n·(corner − p) < 0) to every one of `corners`.
bool back_facing_to_region(const Mesh& mesh, std::size_t f, const std::array<Vec3, 6>& corners);

/// Per face: 1 = kept (front-facing to some corner), 0 = culled for the region.
std::vector<std::uint8_t> regional_back_face_cull(const Mesh& mesh, const std::array<Vec3, 6>& corners);

}  // namespace visimp
