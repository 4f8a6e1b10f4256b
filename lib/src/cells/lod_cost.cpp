// The walkthrough-LOD collapse cost (see lod_cost.h).
#include "visimp/cells/lod_cost.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "visimp/core/errors.h"
#include "visimp/core/face_subset.h"

namespace visimp {

ProjectedLengthCost::ProjectedLengthCost(std::vector<Vec3> eyes, double max_length)
    : eyes_(std::move(eyes)), max_length_(max_length) {
  if (eyes_.empty()) throw UsageError("ProjectedLengthCost needs at least one eye");
  if (!(max_length_ > 0)) throw UsageError("ProjectedLengthCost: the length tolerance must be > 0");
}

void ProjectedLengthCost::set_region(const std::array<Vec3, 6>& hexagon) {
  region_ = hexagon;
  has_region_ = true;
}

double distance_to_hexagon(const std::array<Vec3, 6>& hexagon, const Vec3& p) {
  // In the hexagon's plane (z = its height): 0 inside (left of every counter-clockwise edge),
  // else the nearest edge; then the height difference.
  bool inside = true;
  double planar = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < 6; ++k) {
    const Vec3& a = hexagon[k];
    const Vec3& b = hexagon[(k + 1) % 6];
    const double ex = b.x - a.x, ey = b.y - a.y;
    if (ex * (p.y - a.y) - ey * (p.x - a.x) < 0) inside = false;
    const double t = std::clamp(((p.x - a.x) * ex + (p.y - a.y) * ey) / (ex * ex + ey * ey), 0.0, 1.0);
    planar = std::min(planar, std::hypot(p.x - (a.x + t * ex), p.y - (a.y + t * ey)));
  }
  return std::hypot(inside ? 0.0 : planar, p.z - hexagon[0].z);
}

double ProjectedLengthCost::projected_length(const Vec3& a, const Vec3& b) const {
  double longest = 0;
  const Vec3 edge = b - a, mid = (a + b) * 0.5;
  if (has_region_) {
    const double d = distance_to_hexagon(region_, mid);
    if (!(d > 0)) return std::numeric_limits<double>::infinity();
    longest = norm(edge) / d;
  }
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
  const double length = projected_length(e.p0, e.p1);
  if (length > max_length_) return std::numeric_limits<double>::infinity();
  return bend * bend * length * (std::max(e.w0, kWeightFloor) + std::max(e.w1, kWeightFloor));
}

Mesh build_lod_mesh(const Mesh& object, const std::vector<Vec3>& eyes, const std::vector<float>& weights,
                    std::size_t target_faces, double max_length, const std::array<Vec3, 6>* region) {
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
  ProjectedLengthCost cost(eyes, max_length);
  if (region) cost.set_region(*region);
  SimplifyOptions options;
  options.target_faces = std::max<std::size_t>(1, target_faces);
  options.collapse_cost = &cost;
  options.vertex_weights = front_weights.size() == front.num_vertices() ? front_weights : std::vector<float>{};
  if (front.num_faces() <= options.target_faces) return front;
  return simplify(front, options).mesh;
}

}  // namespace visimp
