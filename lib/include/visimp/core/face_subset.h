// A mesh made of some of another mesh's faces (hidden-face removal, culled views).
#pragma once

#include <cstdint>
#include <vector>

#include "visimp/core/mesh.h"

namespace visimp {

/// The faces with keep[f] != 0, in input order, with their face quality. Vertices that only
/// removed faces used go; every other vertex (isolated ones included) stays, in input order,
/// with its quality.
Mesh keep_faces(const Mesh& mesh, const std::vector<std::uint8_t>& keep);

}  // namespace visimp
