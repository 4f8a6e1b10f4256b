// Leaving out what no camera sees (mission 5): the faces with V at or below a threshold.
#include "visimp/core/errors.h"
#include "visimp/core/face_subset.h"
#include "visimp/visibility/visibility.h"

namespace visimp {

HiddenRemoval drop_hidden_faces(const Mesh& mesh, const std::vector<float>& face_visibility, double threshold) {
  if (face_visibility.size() != mesh.num_faces()) {
    throw UsageError("dropping hidden faces needs V of every face: got " + std::to_string(face_visibility.size()) +
                     " values for " + std::to_string(mesh.num_faces()) + " faces");
  }
  if (!(threshold >= 0 && threshold < 1)) throw UsageError("drop_hidden_faces: the threshold must be in [0, 1)");
  HiddenRemoval r;
  std::vector<std::uint8_t> keep(mesh.num_faces(), 0);
  double total_area = 0;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const double area = 0.5 * norm(face_normal_unnormalized(mesh, mesh.faces[f]));
    total_area += area;
    keep[f] = face_visibility[f] > threshold;
    if (keep[f]) {
      r.face_visibility.push_back(face_visibility[f]);
    } else {
      ++r.faces_removed;
      r.area_removed += area;
    }
  }
  r.mesh = keep_faces(mesh, keep);
  r.area_fraction_removed = total_area > 0 ? r.area_removed / total_area : 0.0;
  return r;
}

}  // namespace visimp
