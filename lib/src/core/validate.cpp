#include "visimp/core/validate.h"

#include <cmath>

#include "visimp/core/errors.h"

namespace visimp {

ValidationReport validate(const Mesh& mesh) {
  ValidationReport r;
  auto note = [&r](const std::string& s) {
    if (r.first_problem.empty()) r.first_problem = s;
  };
  const std::size_t nv = mesh.positions.size();
  for (std::size_t v = 0; v < nv; ++v) {
    if (!is_finite(mesh.positions[v])) {
      ++r.non_finite_coordinates;
      note("vertex " + std::to_string(v) + " has a non-finite coordinate");
    }
  }
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    for (VertexIndex v : mesh.faces[f]) {
      if (v >= nv) {
        ++r.out_of_range_indices;
        note("face " + std::to_string(f) + " has vertex index " + std::to_string(v) + " >= " + std::to_string(nv) +
             " vertices");
      }
    }
  }
  if (!mesh.vertex_quality.empty() && mesh.vertex_quality.size() != nv) {
    ++r.quality_size_mismatches;
    note("vertex quality has " + std::to_string(mesh.vertex_quality.size()) + " values for " + std::to_string(nv) +
         " vertices");
  }
  if (!mesh.face_quality.empty() && mesh.face_quality.size() != mesh.faces.size()) {
    ++r.quality_size_mismatches;
    note("face quality has " + std::to_string(mesh.face_quality.size()) + " values for " +
         std::to_string(mesh.faces.size()) + " faces");
  }
  for (float q : mesh.vertex_quality) r.non_finite_quality += !std::isfinite(q);
  for (float q : mesh.face_quality) r.non_finite_quality += !std::isfinite(q);
  if (r.non_finite_quality) note("a quality value is not finite");
  return r;
}

void require_valid(const Mesh& mesh, const std::string& what) {
  const ValidationReport r = validate(mesh);
  if (!r.ok()) throw InvalidMeshError(what + ": " + r.first_problem);
}

}  // namespace visimp
