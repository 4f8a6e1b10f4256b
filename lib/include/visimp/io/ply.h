// PLY (Turk's polygon file format): ascii, binary_little_endian and binary_big_endian.
// Reads any scalar type for x/y/z, `vertex_indices` or `vertex_index` lists with any count
// and index types, and the vertex and face property `quality`; every other property and
// element is skipped by its declared size. Writes binary little-endian or ascii, with
// `quality` when the mesh has it (MeshLab shows it as a colour map).
#pragma once

#include <iosfwd>
#include <string>
#include <string_view>

#include "visimp/core/mesh.h"
#include "visimp/io/mesh_io.h"

namespace visimp {

/// Throws IoError naming `name` and the line (ascii) or byte offset (binary).
Mesh read_ply(std::string_view bytes, const std::string& name);
void write_ply(const Mesh& mesh, std::ostream& out, const WriteOptions& options);

/// True when float coordinates would move some vertex by more than 1e-7 of the diagonal.
bool needs_double_precision(const Mesh& mesh);

}  // namespace visimp
