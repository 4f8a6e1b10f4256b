#include "visimp/core/spatial_order.h"

#include <algorithm>

#include "visimp/core/bounding_box.h"

namespace visimp {

std::uint32_t morton_code(const Vec3& unit) {
  auto spread = [](double v) {
    std::uint32_t x = static_cast<std::uint32_t>(std::clamp(v, 0.0, 1.0) * 1023.0);
    x = (x | (x << 16)) & 0x030000ffu;
    x = (x | (x << 8)) & 0x0300f00fu;
    x = (x | (x << 4)) & 0x030c30c3u;
    return (x | (x << 2)) & 0x09249249u;
  };
  return (spread(unit.x) << 2) | (spread(unit.y) << 1) | spread(unit.z);
}

std::vector<std::uint32_t> spatial_face_order(const Mesh& mesh) {
  const BoundingBox box = bounding_box(mesh);
  const Vec3 extent = box.max - box.min;
  const double scale = 1.0 / std::max({extent.x, extent.y, extent.z, 1e-300});
  std::vector<std::uint64_t> keyed(mesh.num_faces());
  for (std::size_t f = 0; f < keyed.size(); ++f) {
    // Summed in index order, so the key does not depend on how the face is wound or rotated.
    Face face = mesh.faces[f];
    std::sort(face.begin(), face.end());
    const Vec3 centroid = (mesh.positions[face[0]] + mesh.positions[face[1]] + mesh.positions[face[2]]) / 3.0;
    keyed[f] = (std::uint64_t{morton_code((centroid - box.min) * scale)} << 32) | f;
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::uint32_t> order(keyed.size());
  for (std::size_t i = 0; i < keyed.size(); ++i) order[i] = static_cast<std::uint32_t>(keyed[i] & 0xffffffffu);
  return order;
}

}  // namespace visimp
