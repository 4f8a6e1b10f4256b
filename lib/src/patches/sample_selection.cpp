// Sample selection for view reconstruction (see sample_selection.h).
#include "visimp/patches/sample_selection.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <tuple>

#include "visimp/core/errors.h"

namespace visimp {
namespace {

// Hull faces as camera indices with, per edge k = (v[k], v[k+1]), the plane through the
// centre that bounds the face's cone and the face across that edge.
struct HullFace {
  std::array<std::uint32_t, 3> v;
  std::array<Vec3, 3> edge_normal;  // v[k] × v[k+1]: d is on the face's side when ≥ 0
  std::array<std::uint32_t, 3> across;
};

constexpr int kCubeCells = 16;  // start table: 6 × 16 × 16 cube-map cells

Vec3 cube_cell_direction(int face, int i, int j) {
  const double u = (i + 0.5) / kCubeCells * 2 - 1, v = (j + 0.5) / kCubeCells * 2 - 1;
  const double s = face % 2 == 0 ? 1.0 : -1.0;
  switch (face / 2) {
    case 0:
      return {s, u, v};
    case 1:
      return {u, s, v};
    default:
      return {u, v, s};
  }
}

std::size_t cube_cell(const Vec3& d) {
  const double ax = std::fabs(d.x), ay = std::fabs(d.y), az = std::fabs(d.z);
  int face;
  double u, v, m;
  if (ax >= ay && ax >= az) {
    face = d.x >= 0 ? 0 : 1, u = d.y, v = d.z, m = ax;
  } else if (ay >= az) {
    face = d.y >= 0 ? 2 : 3, u = d.x, v = d.z, m = ay;
  } else {
    face = d.z >= 0 ? 4 : 5, u = d.x, v = d.y, m = az;
  }
  auto index = [&](double t) {
    const int k = static_cast<int>((t / m + 1) / 2 * kCubeCells);
    return std::clamp(k, 0, kCubeCells - 1);
  };
  return (static_cast<std::size_t>(face) * kCubeCells + static_cast<std::size_t>(index(u))) * kCubeCells +
         static_cast<std::size_t>(index(v));
}

}  // namespace

struct SampleSelector::Impl {
  std::optional<SphereTessellation> tessellation;
  std::vector<HullFace> hull;
  std::vector<std::uint32_t> start;  // per cube cell: a hull face near it

  bool inside(const HullFace& f, const Vec3& d) const {
    return dot(f.edge_normal[0], d) >= 0 && dot(f.edge_normal[1], d) >= 0 && dot(f.edge_normal[2], d) >= 0;
  }

  std::uint32_t brute_force(const Vec3& d) const {
    // The face whose worst edge test is least negative (exactly inside when ≥ 0).
    std::uint32_t best = 0;
    double best_margin = -std::numeric_limits<double>::infinity();
    for (std::uint32_t f = 0; f < hull.size(); ++f) {
      const HullFace& h = hull[f];
      const double margin = std::min({dot(h.edge_normal[0], d), dot(h.edge_normal[1], d), dot(h.edge_normal[2], d)});
      if (margin > best_margin) best_margin = margin, best = f;
    }
    return best;
  }

  std::uint32_t walk(const Vec3& d, std::uint32_t f) const {
    // A visibility walk over the hull's central projection: a Delaunay triangulation of the
    // sphere, on which such walks terminate; the step cap is only a guard.
    for (std::size_t step = 0; step <= hull.size(); ++step) {
      const HullFace& h = hull[f];
      int worst = -1;
      double worst_value = 0;
      for (int k = 0; k < 3; ++k) {
        const double value = dot(h.edge_normal[static_cast<std::size_t>(k)], d);
        if (value < worst_value) worst_value = value, worst = k;
      }
      if (worst < 0) return f;
      f = h.across[static_cast<std::size_t>(worst)];
    }
    return brute_force(d);
  }
};

int octahedron_level_of(const CameraSet& cameras) {
  for (int level = 0; level <= SphereTessellation::kMaxLevel; ++level) {
    if (cameras.size() != octahedron_camera_count(level)) continue;
    const CameraSet octahedron = octahedron_cameras(level);
    for (std::size_t i = 0; i < cameras.size(); ++i) {
      const Vec3 &a = cameras.directions[i], &b = octahedron.directions[i];
      if (a.x != b.x || a.y != b.y || a.z != b.z) return -1;
    }
    return level;
  }
  return -1;
}

SampleSelector::SampleSelector(const CameraSet& cameras) : impl_(std::make_unique<Impl>()) {
  const int level = octahedron_level_of(cameras);
  if (level >= 0) {
    impl_->tessellation.emplace(level);
    return;
  }
  using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Point = Kernel::Point_3;
  using HullMesh = CGAL::Surface_mesh<Point>;
  const std::string problem = "the camera directions of '" + cameras.name + "' ";
  std::map<std::tuple<double, double, double>, std::uint32_t> index_of;
  std::vector<Point> points;
  for (std::uint32_t i = 0; i < cameras.size(); ++i) {
    const Vec3& d = cameras.directions[i];
    if (index_of.emplace(std::make_tuple(d.x, d.y, d.z), i).second) points.emplace_back(d.x, d.y, d.z);
  }
  if (points.size() < 4)
    throw UsageError(problem + "are fewer than 4 distinct directions: no hull surrounds the centre");
  HullMesh hull;
  CGAL::convex_hull_3(points.begin(), points.end(), hull);
  auto camera_of = [&](HullMesh::Vertex_index v) {
    const Point& p = hull.point(v);
    return index_of.at(std::make_tuple(p.x(), p.y(), p.z()));
  };
  std::map<HullMesh::Face_index, std::uint32_t> face_number;
  for (HullMesh::Face_index f : hull.faces()) face_number.emplace(f, static_cast<std::uint32_t>(face_number.size()));
  impl_->hull.resize(face_number.size());
  for (const auto& [f, number] : face_number) {
    HullFace& face = impl_->hull[number];
    auto h = hull.halfedge(f);
    for (std::size_t k = 0; k < 3; ++k) {
      // The halfedge h ends at the face's vertex k+1 and starts at vertex k.
      face.v[k] = camera_of(hull.source(h));
      const auto opposite = hull.face(hull.opposite(h));
      if (!opposite.is_valid()) throw UsageError(problem + "do not span a closed hull");
      face.across[k] = face_number.at(opposite);
      h = hull.next(h);
    }
    const auto& d = cameras.directions;
    for (std::size_t k = 0; k < 3; ++k) face.edge_normal[k] = cross(d[face.v[k]], d[face.v[(k + 1) % 3]]);
    // The centre must be strictly inside: every face's cone opens away from it.
    if (!(dot(d[face.v[0]], face.edge_normal[1]) > 0)) {
      throw UsageError(problem + "do not surround the centre (they lie in one plane or half-space)");
    }
  }
  impl_->start.resize(6 * kCubeCells * kCubeCells);
  for (int face = 0; face < 6; ++face) {
    for (int i = 0; i < kCubeCells; ++i) {
      for (int j = 0; j < kCubeCells; ++j) {
        const Vec3 d = cube_cell_direction(face, i, j);
        impl_->start[cube_cell(d)] = impl_->brute_force(d);
      }
    }
  }
}

SampleSelector::~SampleSelector() = default;
SampleSelector::SampleSelector(SampleSelector&&) noexcept = default;
SampleSelector& SampleSelector::operator=(SampleSelector&&) noexcept = default;

bool SampleSelector::hierarchical() const { return impl_->tessellation.has_value(); }

std::size_t SampleSelector::cells() const {
  return impl_->tessellation ? impl_->tessellation->leaf_faces().size() : impl_->hull.size();
}

std::uint32_t SampleSelector::cell(const Vec3& direction) const {
  if (impl_->tessellation) return impl_->tessellation->locate(direction);
  return impl_->walk(direction, impl_->start[cube_cell(direction)]);
}

std::array<std::uint32_t, 3> SampleSelector::corners(std::uint32_t cell) const {
  if (impl_->tessellation) {
    const Face& f = impl_->tessellation->leaf_faces()[cell];
    return {f[0], f[1], f[2]};
  }
  return impl_->hull[cell].v;
}

SampleChoice SampleSelector::samples_of_cell(std::uint32_t cell) const {
  SampleChoice choice;
  const std::array<std::uint32_t, 3> c = corners(cell);
  for (std::uint32_t s : c) choice.samples[choice.count++] = s;
  if (impl_->tessellation) return choice;
  // The vertex of each edge-neighbour that is not on the shared edge.
  for (std::uint32_t neighbour : impl_->hull[cell].across) {
    for (std::uint32_t s : impl_->hull[neighbour].v) {
      const auto end = choice.samples.begin() + static_cast<std::ptrdiff_t>(choice.count);
      if (std::find(choice.samples.begin(), end, s) == end) choice.samples[choice.count++] = s;
    }
  }
  return choice;
}

}  // namespace visimp
