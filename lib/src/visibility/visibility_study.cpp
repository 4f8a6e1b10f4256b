#include "visimp/visibility/visibility_study.h"

#include <cmath>

#include "visimp/cameras/camera_set.h"
#include "visimp/core/errors.h"

namespace visimp {

std::vector<VisibilityStudyRow> visibility_study(const Mesh& mesh, Renderer& renderer, const VisibilityOptions& options,
                                                 int max_level, RenderObserver* observer) {
  if (max_level < 1 || max_level > SphereTessellation::kMaxLevel) {
    throw OptionError(nullptr, "visibility_study: max_level",
                      "must be in 1.." + std::to_string(SphereTessellation::kMaxLevel));
  }
  std::vector<VisibilityStudyRow> rows;
  std::vector<std::vector<float>> values;
  for (int level = 0; level <= max_level; ++level) {
    const Visibility v = compute_visibility(mesh, octahedron_cameras(level), renderer, options);
    rows.push_back({level, octahedron_camera_count(level), v.stats.seconds_total, v.mesh, 0});
    values.push_back(v.face);
    if (observer != nullptr) observer->on_render_progress(static_cast<double>(level + 1) / (max_level + 1));
  }
  const std::vector<float>& reference = values.back();
  std::vector<double> areas(mesh.num_faces());
  double area_sum = 0;
  for (std::size_t f = 0; f < areas.size(); ++f)
    area_sum += areas[f] = norm(face_normal_unnormalized(mesh, mesh.faces[f]));
  for (std::size_t i = 0; i < rows.size(); ++i) {
    double sum = 0;
    for (std::size_t f = 0; f < areas.size(); ++f) sum += areas[f] * std::abs(values[i][f] - reference[f]);
    rows[i].mean_abs_error = area_sum > 0 ? sum / area_sum : 0;
  }
  return rows;
}

}  // namespace visimp
