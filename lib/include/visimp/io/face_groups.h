// Which object each face of a read mesh belongs to: an OBJ's `o`/`g` groups, a scene file's
// nodes (glTF, 3MF, COLLADA, FBX, X3D). Scenes (cells/scene.h) and the visibility field take
// these groups as their objects.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace visimp {

struct FaceGroups {
  std::vector<std::string> names;         ///< in order of first use (a scene node's name, "" when it has none)
  std::vector<std::uint32_t> face_group;  ///< per face of the mesh (after triangulation), into names
};

}  // namespace visimp
