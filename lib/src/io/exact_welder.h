// Welds vertices whose coordinates are exactly equal (+0 and -0 count as equal): how the
// readers of formats that store triangles with their own corners (STL, and the scene formats
// read through assimp, which split vertices at UV and normal seams) rebuild shared vertices.
// Exact equality only: no tolerance, so nothing that was apart in the file is joined.
#pragma once

#include <cstdint>
#include <cstring>
#include <unordered_map>

#include "visimp/core/mesh.h"

namespace visimp::detail {

class ExactWelder {
 public:
  /// Appends new vertices to `mesh.positions`.
  explicit ExactWelder(Mesh& mesh) : mesh_(mesh) {}
  /// The index of the vertex at `p`, added if no earlier vertex of this welder is there.
  VertexIndex add(Vec3 p) {
    if (p.x == 0) p.x = 0;
    if (p.y == 0) p.y = 0;
    if (p.z == 0) p.z = 0;
    const auto [it, inserted] = index_.try_emplace(p, static_cast<VertexIndex>(mesh_.positions.size()));
    if (inserted) mesh_.positions.push_back(p);
    return it->second;
  }

 private:
  struct Hash {
    std::size_t operator()(const Vec3& p) const {
      std::uint64_t h = 1469598103934665603ull;
      for (int k = 0; k < 3; ++k) {
        std::uint64_t bits;
        const double v = p[k];
        std::memcpy(&bits, &v, sizeof bits);
        h = (h ^ bits) * 1099511628211ull;
      }
      return static_cast<std::size_t>(h ^ (h >> 29));
    }
  };
  Mesh& mesh_;
  std::unordered_map<Vec3, VertexIndex, Hash> index_;
};

}  // namespace visimp::detail
