// The walkthrough-LOD collapse cost (see lod_cost.h).
#include "visimp/cells/lod_cost.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "visimp/core/errors.h"
#include "visimp/core/face_subset.h"

namespace visimp {

ProjectedLengthCost::ProjectedLengthCost(std::vector<Vec3> eyes) : eyes_(std::move(eyes)) {
  if (eyes_.empty()) throw UsageError("ProjectedLengthCost needs at least one eye");
}

double ProjectedLengthCost::projected_length(const Vec3& a, const Vec3& b) const {
  double longest = 0;
  const Vec3 edge = b - a, mid = (a + b) * 0.5;
  for (const Vec3& eye : eyes_) {
    const Vec3 to = mid - eye;
    const double distance = norm(to);
    if (!(distance > 0)) return std::numeric_limits<double>::infinity();
    // The part of the edge across the line of sight, over the distance.
    longest = std::max(longest, norm(cross(edge, to)) / (distance * distance));
  }
  return longest;
}

double ProjectedLengthCost::cost(const Edge& e) const {
  constexpr float kWeightFloor = 0.01f;
  const double bend = 1.5 - dot(e.n0, e.n1);
  return bend * bend * projected_length(e.p0, e.p1) * (std::max(e.w0, kWeightFloor) + std::max(e.w1, kWeightFloor));
}

Mesh build_lod_mesh(const Mesh& object, const std::vector<Vec3>& eyes, const std::vector<float>& weights,
                    std::size_t target_faces) {
  if (!weights.empty() && weights.size() != object.num_vertices())
    throw UsageError("build_lod_mesh: one weight per vertex expected");
  std::vector<std::uint8_t> keep(object.num_faces(), 0);
  for (std::size_t f = 0; f < object.num_faces(); ++f) {
    const Vec3 n = face_normal_unnormalized(object, object.faces[f]);
    for (const Vec3& eye : eyes) {
      if (dot(n, eye - object.positions[object.faces[f][0]]) > 0) keep[f] = 1;
    }
  }
  // keep_faces keeps, in input order, the vertices of kept faces and isolated ones: map the
  // weights the same way.
  const Mesh front = keep_faces(object, keep);
  std::vector<float> front_weights;
  if (!weights.empty()) {
    std::vector<std::uint8_t> used(object.num_vertices(), 0), kept(object.num_vertices(), 0);
    for (std::size_t f = 0; f < object.num_faces(); ++f) {
      for (VertexIndex v : object.faces[f]) {
        used[v] = 1;
        if (keep[f]) kept[v] = 1;
      }
    }
    for (std::size_t v = 0; v < object.num_vertices(); ++v) {
      if (kept[v] || !used[v]) front_weights.push_back(weights[v]);
    }
  }
  const ProjectedLengthCost cost(eyes);
  SimplifyOptions options;
  options.target_faces = std::max<std::size_t>(1, target_faces);
  options.collapse_cost = &cost;
  options.vertex_weights = front_weights.size() == front.num_vertices() ? front_weights : std::vector<float>{};
  if (front.num_faces() <= options.target_faces) return front;
  return simplify(front, options).mesh;
}

}  // namespace visimp
