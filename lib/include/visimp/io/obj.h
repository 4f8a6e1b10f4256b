// Wavefront OBJ: `v x y z [w]` and `f` with a, a/b, a//c, a/b/c forms and negative
// (relative) indices; polygons are fan-triangulated. Other statements (vt, vn, g, o, s,
// usemtl, mtllib, l, p) are ignored. Writes `v` and `f` lines.
#pragma once

#include <iosfwd>
#include <string>
#include <string_view>

#include "visimp/core/mesh.h"

namespace visimp {

Mesh read_obj(std::string_view text, const std::string& name);
void write_obj(const Mesh& mesh, std::ostream& out);

}  // namespace visimp
