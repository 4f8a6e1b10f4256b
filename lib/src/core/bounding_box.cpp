#include "visimp/core/bounding_box.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace visimp {

BoundingBox bounding_box(const Mesh& mesh) {
  BoundingBox box;
  if (mesh.faces.empty()) {
    for (const Vec3& p : mesh.positions) box.extend(p);
    return box;
  }
  // Mark the referenced vertices, then scan the positions in order: a byte per vertex instead
  // of three random 24-byte reads per face (0.13 s -> 0.025 s a call at 14M faces;
  // visibility asks five times).
  std::vector<std::uint8_t> used(mesh.positions.size(), 0);
  for (const Face& f : mesh.faces) used[f[0]] = used[f[1]] = used[f[2]] = 1;
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v]) box.extend(mesh.positions[v]);
  return box;
}

UnitFrame unit_frame(const BoundingBox& box) {
  UnitFrame frame;
  frame.center = box.center();
  const double d = box.diagonal();
  frame.scale = (d > 0 && std::isfinite(d)) ? 1.0 / d : 1.0;
  return frame;
}

}  // namespace visimp
