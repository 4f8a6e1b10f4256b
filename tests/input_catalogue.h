// The bad-input catalogue (issue 6): broken files every reader must refuse with one clear
// message, and valid-but-extreme meshes every stage must get through with finite output.
// Used by the reader tests (in memory) and the app tests (as files, end to end).
#pragma once

#include <string>
#include <vector>

#include "visimp/core/mesh.h"
#include "visimp/io/mesh_io.h"

namespace visimp::test {

struct BadInput {
  std::string name;
  std::string file;  ///< file name whose extension selects the reader ("x.ply")
  std::string bytes;
  std::string expected;  ///< a fragment of the error message
  /// A well-formed file with nothing in it to simplify, measure or compare (no faces): the
  /// readers accept it, the commands refuse it.
  bool readable = false;
};

/// At least 60 invalid inputs across PLY, OBJ, OFF and STL, with missing, unknown and wrong
/// extensions.
std::vector<BadInput> bad_inputs();

struct ExtremeMesh {
  std::string name;
  Mesh mesh;
};

/// Valid meshes at the edges: far offsets, tiny and huge scales, coplanar, slivers, many
/// zero-area faces, duplicates, non-manifold edges, isolated vertices, flipped faces.
std::vector<ExtremeMesh> extreme_meshes();

}  // namespace visimp::test
