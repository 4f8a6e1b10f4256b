// How V converges with the number of cameras (Zhang & Turk 2002, Fig. 3): V with the
// octahedron sets of levels 0..K (6, 18, 66, 258, 1026, 4098 cameras), each compared with the
// finest by the area-weighted mean |V - V_ref|, with the seconds each took.
#pragma once

#include <cstddef>
#include <vector>

#include "visimp/core/mesh.h"
#include "visimp/render/renderer.h"
#include "visimp/visibility/visibility.h"

namespace visimp {

struct VisibilityStudyRow {
  int level = 0;            ///< octahedron level
  std::size_t cameras = 0;  ///< 4^(level+1) + 2
  double seconds = 0;       ///< the whole measure at this level (refinement included)
  double mesh_visibility = 0;
  double mean_abs_error = 0;  ///< area-weighted mean |V - V(level max_level)|; 0 for the last row
};

/// One row per level 0..max_level (1..5); throws OptionError for a level out of range.
/// `observer` receives the fraction of levels done.
std::vector<VisibilityStudyRow> visibility_study(const Mesh& mesh, Renderer& renderer, const VisibilityOptions& options,
                                                 int max_level, RenderObserver* observer = nullptr);

}  // namespace visimp
