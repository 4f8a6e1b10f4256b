// validate(mesh): the contract checker called after every mutation in tests and before
// any algorithm trusts a mesh. It checks what would make an algorithm crash or emit NaN;
// topological oddities (non-manifold edges, holes) are legal and reported by analyze().
#pragma once

#include <cstddef>
#include <string>

#include "visimp/core/mesh.h"

namespace visimp {

struct ValidationReport {
  std::size_t out_of_range_indices = 0;     ///< face indices >= num_vertices
  std::size_t non_finite_coordinates = 0;   ///< vertices with a NaN or infinite coordinate
  std::size_t quality_size_mismatches = 0;  ///< quality arrays neither empty nor one per element
  std::size_t non_finite_quality = 0;       ///< NaN or infinite quality values
  std::string first_problem;                ///< human-readable description of the first issue

  bool ok() const {
    return out_of_range_indices == 0 && non_finite_coordinates == 0 && quality_size_mismatches == 0 &&
           non_finite_quality == 0;
  }
};

ValidationReport validate(const Mesh& mesh);

/// Throws InvalidMeshError("<what>: <first problem>") when validate(mesh) is not ok.
void require_valid(const Mesh& mesh, const std::string& what);

}  // namespace visimp
