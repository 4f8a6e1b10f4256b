// STL, binary and ascii. STL stores unshared triangle corners: the reader welds corners whose
// coordinates are bit-for-bit equal (no tolerance, so nothing distinct is merged). A binary
// file must hold exactly the declared number of triangles.
#pragma once

#include <iosfwd>
#include <string>
#include <string_view>

#include "visimp/core/mesh.h"

namespace visimp {

Mesh read_stl(std::string_view bytes, const std::string& name);
void write_stl(const Mesh& mesh, std::ostream& out, bool binary);

}  // namespace visimp
