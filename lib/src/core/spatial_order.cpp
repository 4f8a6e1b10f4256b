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

namespace {

// Indices 0..n-1 stably sorted by a 30-bit key: three 10-bit passes of an LSD radix sort
// (linear; std::sort of 64-bit keys took over a second at 14M faces). Equal keys keep index order.
std::vector<std::uint32_t> order_by_key(const std::vector<std::uint32_t>& key) {
  constexpr int kBits = 10, kBuckets = 1 << kBits;
  const std::size_t n = key.size();
  std::vector<std::uint32_t> order(n), scratch(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<std::uint32_t>(i);
  for (int shift = 0; shift < 30; shift += kBits) {
    std::vector<std::size_t> start(kBuckets + 1, 0);
    for (std::uint32_t i : order) ++start[((key[i] >> shift) & (kBuckets - 1)) + 1];
    for (int b = 0; b < kBuckets; ++b) start[b + 1] += start[b];
    for (std::uint32_t i : order) scratch[start[(key[i] >> shift) & (kBuckets - 1)]++] = i;
    order.swap(scratch);
  }
  return order;
}

// Morton codes of points in the mesh's bounding box, scaled by its longest side.
struct MortonBox {
  explicit MortonBox(const Mesh& mesh) : box(bounding_box(mesh)) {
    const Vec3 extent = box.max - box.min;
    scale = 1.0 / std::max({extent.x, extent.y, extent.z, 1e-300});
  }
  std::uint32_t operator()(const Vec3& p) const { return morton_code((p - box.min) * scale); }
  BoundingBox box;
  double scale = 1;
};

}  // namespace

std::vector<std::uint32_t> spatial_face_order(const Mesh& mesh) {
  const MortonBox code(mesh);
  std::vector<std::uint32_t> key(mesh.num_faces());
  for (std::size_t f = 0; f < key.size(); ++f) {
    // Summed in index order, so the key does not depend on how the face is wound or rotated.
    Face face = mesh.faces[f];
    std::sort(face.begin(), face.end());
    const Vec3 centroid = (mesh.positions[face[0]] + mesh.positions[face[1]] + mesh.positions[face[2]]) / 3.0;
    key[f] = code(centroid);
  }
  return order_by_key(key);
}

std::vector<std::uint32_t> spatial_vertex_order(const Mesh& mesh) {
  const MortonBox code(mesh);
  std::vector<std::uint32_t> key(mesh.num_vertices());
  for (std::size_t v = 0; v < key.size(); ++v) key[v] = code(mesh.positions[v]);
  return order_by_key(key);
}

}  // namespace visimp
