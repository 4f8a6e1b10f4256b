// Regional conservative back-face culling (see regional_culling.h).
#include "visimp/cells/regional_culling.h"

namespace visimp {

bool back_facing_to_region(const Mesh& mesh, std::size_t f, const std::array<Vec3, 6>& corners) {
  const Face& face = mesh.faces[f];
  const Vec3 n = face_normal_unnormalized(mesh, face);
  const Vec3& p = mesh.positions[face[0]];
  for (const Vec3& c : corners) {
    if (!(dot(n, c - p) < 0)) return false;  // zero or NaN: not provably back-facing, keep it
  }
  return true;
}

std::vector<std::uint8_t> regional_back_face_cull(const Mesh& mesh, const std::array<Vec3, 6>& corners) {
  std::vector<std::uint8_t> keep(mesh.num_faces());
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) keep[f] = back_facing_to_region(mesh, f, corners) ? 0 : 1;
  return keep;
}

}  // namespace visimp
