#include "visimp/core/bounding_box.h"

#include <algorithm>

namespace visimp {

void BoundingBox::extend(const Vec3& p) {
  min = {std::min(min.x, p.x), std::min(min.y, p.y), std::min(min.z, p.z)};
  max = {std::max(max.x, p.x), std::max(max.y, p.y), std::max(max.z, p.z)};
}

BoundingBox bounding_box(const Mesh& mesh) {
  BoundingBox box;
  if (mesh.faces.empty()) {
    for (const Vec3& p : mesh.positions) box.extend(p);
    return box;
  }
  for (const Face& f : mesh.faces)
    for (VertexIndex v : f) box.extend(mesh.positions[v]);
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
