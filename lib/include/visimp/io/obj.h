// Wavefront OBJ: `v x y z [w]` and `f` with a, a/b, a//c, a/b/c forms and negative
// (relative) indices; polygons are fan-triangulated. `o` and `g` name the group of the faces
// after them (read_obj can report it per face, for scenes); other statements (vt, vn, s,
// usemtl, mtllib, l, p) are ignored. Writes `v` and `f` lines.
#pragma once

#include <iosfwd>
#include <string>
#include <string_view>
#include <vector>
#include <cstdint>

#include "visimp/core/mesh.h"
#include "visimp/io/face_groups.h"

namespace visimp {

Mesh read_obj(std::string_view text, const std::string& name);

/// The group of every face: the latest `o` or `g` line before it ("" before any).
using ObjGroups = FaceGroups;
Mesh read_obj(std::string_view text, const std::string& name, ObjGroups* groups);
void write_obj(const Mesh& mesh, std::ostream& out);

}  // namespace visimp
