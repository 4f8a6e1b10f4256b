// Orders along a Morton (Z-order) curve: elements close in the order are close in space, so
// loops that visit them in this order keep their data in cache (rasterizing, tallying) and
// consecutive queries have nearby answers (closest-point hints).
#pragma once

#include <cstdint>
#include <vector>

#include "visimp/core/mesh.h"

namespace visimp {

/// 30-bit Morton code of a point in [0, 1]^3 (10 bits per axis; outside values are clamped).
std::uint32_t morton_code(const Vec3& unit);

/// The faces of `mesh` sorted by the Morton code of their centroids in its bounding box
/// (ties by index, so the order is deterministic). `threads` (0 = one per hardware thread)
/// share the codes; the order does not depend on it.
std::vector<std::uint32_t> spatial_face_order(const Mesh& mesh, unsigned threads = 0);

/// The vertices of `mesh` sorted by the Morton code of their positions (ties by index).
/// `threads` as for spatial_face_order; the order does not depend on it.
std::vector<std::uint32_t> spatial_vertex_order(const Mesh& mesh, unsigned threads = 1);

}  // namespace visimp
