// FNV-1a content hashes: identify the mesh or camera set a derived file (tally, bitfields)
// belongs to, so a file is never applied to the wrong input.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "visimp/core/mesh.h"

namespace visimp {

constexpr std::uint64_t kFnvOffset = 0xcbf29ce484222325ull;

/// Continues `hash` over `size` raw bytes.
inline std::uint64_t fnv1a(std::uint64_t hash, const void* data, std::size_t size) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= bytes[i];
    hash *= 0x100000001b3ull;
  }
  return hash;
}

/// Of the positions and faces (not the quality): the geometry a result was computed on.
inline std::uint64_t hash_mesh(const Mesh& mesh) {
  const std::uint64_t h = fnv1a(kFnvOffset, mesh.positions.data(), mesh.positions.size() * sizeof(Vec3));
  return fnv1a(h, mesh.faces.data(), mesh.faces.size() * sizeof(Face));
}

inline std::uint64_t hash_directions(const std::vector<Vec3>& directions) {
  return fnv1a(kFnvOffset, directions.data(), directions.size() * sizeof(Vec3));
}

}  // namespace visimp
