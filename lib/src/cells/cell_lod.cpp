// Per-cell LOD derivation (see cell_lod.h).
#include "visimp/cells/cell_lod.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "visimp/cells/lod_cost.h"
#include "visimp/cells/regional_culling.h"
#include "visimp/cells/view_weights.h"
#include "visimp/core/bounding_box.h"
#include "visimp/core/errors.h"
#include "visimp/simplify/simplify.h"

namespace visimp {
namespace {

constexpr double kDegree = M_PI / 180;

Mesh transformed(const Mesh& mesh, const Transform& t) {
  Mesh out;
  out.positions.reserve(mesh.positions.size());
  for (const Vec3& p : mesh.positions) out.positions.push_back(transform_point(t, p));
  out.faces = mesh.faces;
  const double det =
      t[0] * (t[5] * t[10] - t[6] * t[9]) - t[1] * (t[4] * t[10] - t[6] * t[8]) + t[2] * (t[4] * t[9] - t[5] * t[8]);
  if (det < 0) {
    for (Face& f : out.faces) std::swap(f[1], f[2]);
  }
  return out;
}

}  // namespace

void check_options(const CellBuildOptions& o) {
  if (!(o.ts_pixels >= 0) || !std::isfinite(o.ts_pixels)) throw UsageError("--ts must be a finite number >= 0");
  if (!(o.tl_pixels > 0) || !std::isfinite(o.tl_pixels)) throw UsageError("--tl must be a finite number > 0");
  if (o.output_resolution < 16 || o.output_resolution > 8192) throw UsageError("--resolution must be in [16, 8192]");
  if (!(o.fov_degrees > 1 && o.fov_degrees < 170)) throw UsageError("--fov must be in (1, 170) degrees");
  if (o.max_capture_resolution < 32 || o.max_capture_resolution > 4096)
    throw UsageError("--max-capture must be in [32, 4096]");
  if (o.base_levels < 0 || o.base_levels > 12) throw UsageError("--base-levels must be in [0, 12]");
  if (o.max_texture_resolution < 16 || o.max_texture_resolution > 4096)
    throw UsageError("--max-texture must be in [16, 4096]");
}

const char* to_string(LodKind kind) {
  switch (kind) {
    case LodKind::full:
      return "full";
    case LodKind::svmesh:
      return "svmesh";
    case LodKind::mvmesh:
      return "mvmesh";
  }
  return "?";
}

std::size_t CellLods::faces() const {
  std::size_t n = 0;
  for (const CellEntry& e : entries) n += e.kind == LodKind::full ? e.faces.size() : e.mesh.num_faces();
  return n;
}

int capture_resolution(double half_angle, double pixel_angle, int cap) {
  const double half = std::min(half_angle * 1.05, 85 * kDegree);
  const double pixels = std::ceil(2 * std::tan(half) / std::max(pixel_angle, 1e-9));
  return static_cast<int>(std::clamp(pixels, 32.0, static_cast<double>(cap)));
}

CellLodBuilder::CellLodBuilder(const Scene& scene, const HexGrid& grid, const CellBuildOptions& options)
    : scene_(scene), grid_(grid), options_(options) {
  check_options(options_);
  pixel_angle_ = 2 * std::tan(0.5 * options_.fov_degrees * kDegree) / options_.output_resolution;
  // Coarser versions of each mesh, 1/4 of the faces each, in one quadric run.
  versions_.resize(scene.meshes.size());
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    std::vector<std::size_t> targets;
    for (std::size_t k = 1, n = mesh.num_faces() / 4; static_cast<int>(k) <= options_.base_levels && n >= 64;
         ++k, n /= 4)
      targets.push_back(n);
    if (targets.empty()) continue;
    SimplifyOptions so;
    so.target_faces = targets.back();
    const double diagonal = bounding_box(mesh).diagonal();
    for (Simplified& level : simplify_levels(mesh, so, targets)) {
      if (level.mesh.num_faces() == 0) break;
      versions_[m].push_back({std::move(level.mesh), level.result.max_error * diagonal});
    }
  }
  placed_.resize(scene.objects.size());
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const SceneObject& o = scene.objects[i];
    const Mesh& mesh = scene.meshes[o.mesh];
    BoundingBox box;
    for (const Vec3& p : mesh.positions) box.extend(transform_point(o.transform, p));
    Placed& p = placed_[i];
    p.centre = box.center();
    p.radius = 0.5 * box.diagonal();
    p.footprint = 0.5 * std::hypot(box.max.x - box.min.x, box.max.y - box.min.y);
    const Transform& t = o.transform;
    for (int c = 0; c < 3; ++c)
      p.scale = std::max(p.scale, std::sqrt(t[static_cast<std::size_t>(c)] * t[static_cast<std::size_t>(c)] +
                                            t[static_cast<std::size_t>(4 + c)] * t[static_cast<std::size_t>(4 + c)] +
                                            t[static_cast<std::size_t>(8 + c)] * t[static_cast<std::size_t>(8 + c)]));
  }
  if (options_.textures) {
    object_sets_.resize(scene.objects.size());
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
      object_sets_[i].add(scene.object_mesh(i), nullptr, static_cast<std::uint32_t>(i));
      object_sets_[i].finish();
    }
  }
}

bool CellLodBuilder::inside(std::size_t object, const HexCell& cell) const {
  const Placed& p = placed_[object];
  return distance_to_hexagon(grid_.corners(cell), Vec3{p.centre.x, p.centre.y, grid_.eye_height()}) <= p.footprint;
}

Mesh CellLodBuilder::version_for(std::size_t object, double nearest_distance, std::uint32_t* source_faces) const {
  const SceneObject& o = scene_.objects[object];
  const Placed& p = placed_[object];
  // The coarsest version whose error, seen from the cell's nearest point, is under half a pixel.
  const Mesh* best = &scene_.meshes[o.mesh];
  for (const Version& v : versions_[o.mesh]) {
    if (v.error * p.scale <= 0.5 * pixel_angle_ * nearest_distance) best = &v.mesh;
  }
  *source_faces = static_cast<std::uint32_t>(best->num_faces());
  return transformed(*best, o.transform);
}

CellLods CellLodBuilder::build(const HexCell& cell) const {
  CellLods out;
  out.cell = cell;
  const Vec3 centre = grid_.eye_at_center(cell);
  const std::array<Vec3, 6> corners = grid_.corners(cell);
  const double tl = options_.tl_pixels * pixel_angle_;
  const int cap = options_.max_capture_resolution;
  out.entries.resize(scene_.objects.size());
  for (std::size_t i = 0; i < scene_.objects.size(); ++i) {
    CellEntry& entry = out.entries[i];
    entry.object = static_cast<std::uint32_t>(i);
    if (inside(i, cell)) {
      const Mesh mesh = scene_.object_mesh(i);
      const std::vector<std::uint8_t> keep = regional_back_face_cull(mesh, corners);
      for (std::size_t f = 0; f < keep.size(); ++f)
        if (keep[f]) entry.faces.push_back(static_cast<std::uint32_t>(f));
      entry.source_faces = static_cast<std::uint32_t>(mesh.num_faces());
      continue;
    }
    const Placed& p = placed_[i];
    // Nearest approach of any eye in the cell to the object's bounding sphere.
    const double to_centre = norm(p.centre - centre);
    const double nearest = std::max(to_centre - grid_.size() - p.radius, 1e-3 * std::max(p.radius, 1e-30));
    const Mesh object = version_for(i, nearest, &entry.source_faces);
    const double half_angle = to_centre > p.radius ? std::asin(p.radius / to_centre) : 85 * kDegree;
    const int resolution = capture_resolution(half_angle, pixel_angle_, cap);
    const double fov = std::min(170.0, 2 * std::min(half_angle * 1.05, 85 * kDegree) / kDegree);
    // s, in capture pixels, is in output pixels too: the capture's pixels are the output's
    // size unless the cap made them larger (then s is scaled up to output pixels).
    const double capture_pixel = 2 * std::tan(0.5 * fov * kDegree) / resolution;
    const double s = self_occluding_error(object, centre, corners, resolution, fov) * capture_pixel / pixel_angle_;
    entry.self_occluding_error = static_cast<float>(s);
    if (s <= options_.ts_pixels) {
      entry.kind = LodKind::svmesh;
      const DepthImage depth = capture_depth(object, centre, resolution);
      entry.mesh = build_lod_mesh(object, {centre}, depth_variation_weights(object, depth), 1, tl);
      if (options_.textures)
        entry.textures.push_back(capture_texture(object_sets_[i], centre, p.centre, p.radius,
                                                 capture_resolution(half_angle, pixel_angle_,
                                                                    options_.max_texture_resolution)));
    } else {
      entry.kind = LodKind::mvmesh;
      std::vector<float> weights(object.num_vertices(), 0.0f);
      std::vector<Vec3> views{centre};
      for (const HexCell& n : grid_.neighbours(cell)) views.push_back(grid_.eye_at_center(n));
      for (const Vec3& eye : views) {
        const double d = norm(p.centre - eye);
        const double h = d > p.radius ? std::asin(p.radius / d) : 85 * kDegree;
        const std::vector<float> w =
            depth_variation_weights(object, capture_depth(object, eye, capture_resolution(h, pixel_angle_, cap)));
        for (std::size_t v = 0; v < weights.size(); ++v) weights[v] = std::max(weights[v], w[v]);
      }
      std::vector<Vec3> eyes{centre};
      eyes.insert(eyes.end(), corners.begin(), corners.end());
      entry.mesh = build_lod_mesh(object, eyes, weights, 1, tl, &corners);
      if (options_.textures) {
        for (const Vec3& eye : eyes) {
          const double d = norm(p.centre - eye);
          const double h = d > p.radius ? std::asin(p.radius / d) : 85 * kDegree;
          entry.textures.push_back(capture_texture(
              object_sets_[i], eye, p.centre, p.radius, capture_resolution(h, pixel_angle_, options_.max_texture_resolution)));
        }
      }
    }
  }
  return out;
}

}  // namespace visimp
