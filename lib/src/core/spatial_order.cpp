#include "visimp/core/spatial_order.h"

#include <algorithm>

#include "visimp/core/bounding_box.h"
#include "visimp/core/parallel.h"

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
// (linear; std::sort of 64-bit keys took over a second at 14M faces). Equal keys keep index
// order. Each pass splits the input into one contiguous part per worker: the parts count
// their buckets, and scatter behind the earlier parts' entries of each bucket, so the
// order is the serial one for any thread count.
std::vector<std::uint32_t> order_by_key(const std::vector<std::uint32_t>& key, unsigned threads) {
  constexpr int kBits = 10, kBuckets = 1 << kBits;
  const std::size_t n = key.size();
  const unsigned parts = worker_count(threads, n / (1 << 18) + 1);
  const std::size_t part_size = (n + parts - 1) / parts;
  std::vector<std::uint32_t> order(n), scratch(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<std::uint32_t>(i);
  std::vector<std::vector<std::size_t>> start(parts, std::vector<std::size_t>(kBuckets));
  for (int shift = 0; shift < 30; shift += kBits) {
    auto bucket = [&](std::uint32_t i) { return (key[i] >> shift) & (kBuckets - 1); };
    parallel_ranges(n, part_size, parts, [&](std::size_t begin, std::size_t end) {
      std::vector<std::size_t>& count = start[begin / part_size];
      std::fill(count.begin(), count.end(), 0);
      for (std::size_t k = begin; k < end; ++k) ++count[bucket(order[k])];
    });
    std::size_t offset = 0;
    for (int b = 0; b < kBuckets; ++b) {
      for (std::vector<std::size_t>& part : start) {
        const std::size_t count = part[b];
        part[b] = offset;
        offset += count;
      }
    }
    parallel_ranges(n, part_size, parts, [&](std::size_t begin, std::size_t end) {
      std::vector<std::size_t>& next = start[begin / part_size];
      for (std::size_t k = begin; k < end; ++k) scratch[next[bucket(order[k])]++] = order[k];
    });
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

std::vector<std::uint32_t> spatial_face_order(const Mesh& mesh, unsigned threads) {
  const MortonBox code(mesh);
  std::vector<std::uint32_t> key(mesh.num_faces());
  parallel_ranges(key.size(), 1 << 16, worker_count(threads, key.size()), [&](std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f) {
      // Summed in index order, so the key does not depend on how the face is wound or rotated.
      Face face = mesh.faces[f];
      std::sort(face.begin(), face.end());
      const Vec3 centroid = (mesh.positions[face[0]] + mesh.positions[face[1]] + mesh.positions[face[2]]) / 3.0;
      key[f] = code(centroid);
    }
  });
  return order_by_key(key, threads);
}

std::vector<std::uint32_t> spatial_vertex_order(const Mesh& mesh, unsigned threads) {
  const MortonBox code(mesh);
  std::vector<std::uint32_t> key(mesh.num_vertices());
  parallel_ranges(key.size(), 1 << 16, worker_count(threads, key.size()), [&](std::size_t begin, std::size_t end) {
    for (std::size_t v = begin; v < end; ++v) key[v] = code(mesh.positions[v]);
  });
  return order_by_key(key, threads);
}

}  // namespace visimp
