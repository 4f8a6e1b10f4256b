// Object File Format: an `OFF` header (also COFF, NOFF, CNOFF: the extra per-vertex values
// are skipped), counts, one vertex per line, then `n i0 .. in-1 [colour]` per face.
#pragma once

#include <iosfwd>
#include <string>
#include <string_view>

#include "visimp/core/mesh.h"

namespace visimp {

Mesh read_off(std::string_view text, const std::string& name);
void write_off(const Mesh& mesh, std::ostream& out);

}  // namespace visimp
