#include "visimp/core/face_subset.h"

#include "visimp/core/errors.h"

namespace visimp {

Mesh keep_faces(const Mesh& mesh, const std::vector<std::uint8_t>& keep) {
  if (keep.size() != mesh.num_faces()) throw UsageError("keep_faces: one flag per face expected");
  Mesh out;
  std::vector<std::uint8_t> used(mesh.num_vertices(), 0);  // bit 0: by any face, bit 1: by a kept face
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    for (VertexIndex v : mesh.faces[f]) used[v] |= static_cast<std::uint8_t>(keep[f] ? 3 : 1);
  }
  std::vector<VertexIndex> remap(mesh.num_vertices(), 0);
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
    if (used[v] == 1) continue;
    remap[v] = static_cast<VertexIndex>(out.positions.size());
    out.positions.push_back(mesh.positions[v]);
    if (mesh.has_vertex_quality()) out.vertex_quality.push_back(mesh.vertex_quality[v]);
  }
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    if (!keep[f]) continue;
    const Face& face = mesh.faces[f];
    out.faces.push_back({remap[face[0]], remap[face[1]], remap[face[2]]});
    if (mesh.has_face_quality()) out.face_quality.push_back(mesh.face_quality[f]);
  }
  return out;
}

}  // namespace visimp
