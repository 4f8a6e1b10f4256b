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
#include "visimp/core/face_subset.h"
#include "visimp/simplify/simplify.h"

namespace visimp {
namespace {

constexpr double kDegree = M_PI / 180;

}  // namespace

void check_options(const CellBuildOptions& o) {
  if (!(o.ts_pixels >= 0) || !std::isfinite(o.ts_pixels)) throw UsageError("--ts must be a finite number >= 0");
  if (!(o.tl_pixels > 0) || !std::isfinite(o.tl_pixels)) throw UsageError("--tl must be a finite number > 0");
  if (o.output_resolution < 16 || o.output_resolution > 8192) throw UsageError("--resolution must be in [16, 8192]");
  if (!(o.fov_degrees > 1 && o.fov_degrees < 170)) throw UsageError("--fov must be in (1, 170) degrees");
  if (o.max_capture_resolution < 32 || o.max_capture_resolution > 4096)
    throw UsageError("--max-capture must be in [32, 4096]");
  if (o.base_levels < 0 || o.base_levels > 12) throw UsageError("--base-levels must be in [0, 12]");
  if (o.max_cluster < 1 || o.max_cluster > 1000) throw UsageError("--max-cluster must be in [1, 1000]");
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
    case LodKind::in_cluster:
      return "in_cluster";
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

namespace {

// An object's projection from the cell centre, as a disc on the sphere of directions.
struct Disc {
  Vec3 direction;
  double radius = 0;  // angular
};

// Area of the lens where two discs overlap (small-angle, planar).
double overlap(const Disc& a, const Disc& b) {
  const double d = std::acos(std::clamp(dot(a.direction, b.direction), -1.0, 1.0));
  const double r = a.radius, R = b.radius;
  if (d >= r + R) return 0;
  if (d <= std::abs(R - r)) return M_PI * std::min(r, R) * std::min(r, R);
  const double x = std::clamp((d * d + r * r - R * R) / (2 * d * r), -1.0, 1.0);
  const double y = std::clamp((d * d + R * R - r * r) / (2 * d * R), -1.0, 1.0);
  return r * r * std::acos(x) + R * R * std::acos(y) -
         0.5 * std::sqrt(std::max(0.0, (-d + r + R) * (d + r - R) * (d - r + R) * (d + r + R)));
}

Mesh merged(const std::vector<const Mesh*>& parts) {
  Mesh out;
  for (const Mesh* m : parts) {
    const auto base = static_cast<VertexIndex>(out.positions.size());
    out.positions.insert(out.positions.end(), m->positions.begin(), m->positions.end());
    for (const Face& f : m->faces) out.faces.push_back({f[0] + base, f[1] + base, f[2] + base});
  }
  return out;
}

// Faces of `mesh` front-facing to `eye` and not hidden there: shown in an ID image, or with a
// vertex no nearer surface covers (the vertex rule keeps sub-pixel faces).
std::vector<std::uint32_t> seen_faces(const Mesh& mesh, const Vec3& eye, int resolution) {
  const BoundingBox box = bounding_box(mesh);
  const double radius = 0.5 * box.diagonal(), distance = norm(box.center() - eye);
  const double half = distance > radius ? std::min(std::asin(radius / distance) * 1.05, 85 * kDegree) : 85 * kDegree;
  const double near = std::max(1e-4 * std::max(radius, 1e-30), 0.5 * (distance - radius));
  PerspectiveView view = PerspectiveView::looking_at(eye, box.center(), 2 * half / kDegree, resolution, near);
  std::vector<std::array<float, 3>> relative(mesh.num_vertices());
  for (std::size_t v = 0; v < relative.size(); ++v) {
    const Vec3 q = mesh.positions[v] - eye;
    relative[v] = {static_cast<float>(q.x), static_cast<float>(q.y), static_cast<float>(q.z)};
  }
  PerspectiveView local = view;
  local.eye = Vec3{0, 0, 0};
  PerspectiveRasterizer raster;
  PerspectiveFrame frame;
  raster.draw(relative, mesh.faces, nullptr, local, frame);
  std::vector<std::uint8_t> shown(mesh.num_faces(), 0), vertex_free(mesh.num_vertices(), 0);
  for (std::uint32_t id : frame.ids)
    if (id) shown[id - 1] = 1;
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3 q = mesh.positions[v] - eye;
    const double z = dot(q, view.forward);
    if (!(z > near)) continue;
    const double scale = 0.5 * resolution / (z * view.tan_half_fov);
    const double px = dot(q, view.right) * scale + 0.5 * resolution, py = dot(q, view.up) * scale + 0.5 * resolution;
    if (!(px >= 0 && py >= 0 && px < resolution && py < resolution)) continue;
    const float depth = static_cast<float>(1 - near / z);
    const int i0 = static_cast<int>(px), j0 = static_cast<int>(py);
    for (int j = std::max(0, j0 - 1); j <= std::min(resolution - 1, j0 + 1) && !vertex_free[v]; ++j)
      for (int i = std::max(0, i0 - 1); i <= std::min(resolution - 1, i0 + 1); ++i)
        if (frame.depth[static_cast<std::size_t>(j) * resolution + i] >= depth - 1e-4f) vertex_free[v] = 1;
  }
  std::vector<std::uint32_t> out;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const Face& t = mesh.faces[f];
    if (!(dot(face_normal_unnormalized(mesh, t), eye - mesh.positions[t[0]]) > 0)) continue;
    if (shown[f] || vertex_free[t[0]] || vertex_free[t[1]] || vertex_free[t[2]]) out.push_back(static_cast<std::uint32_t>(f));
  }
  return out;
}

}  // namespace

CellLods CellLodBuilder::build(const HexCell& cell) const {
  CellLods out;
  out.cell = cell;
  const Vec3 centre = grid_.eye_at_center(cell);
  const std::array<Vec3, 6> corners = grid_.corners(cell);
  const double tl = options_.tl_pixels * pixel_angle_;
  const int cap = options_.max_capture_resolution;
  const std::size_t n = scene_.objects.size();
  out.entries.resize(n);
  // Per outside object: the version collapsed from, and what the Ts test needs.
  struct Outside {
    Mesh object;
    double half_angle = 0;
    int resolution = 32;
  };
  std::vector<Outside> outside(n);
  std::vector<std::size_t> passing;  // s <= Ts
  auto fov_of = [](double half_angle) { return std::min(170.0, 2 * std::min(half_angle * 1.05, 85 * kDegree) / kDegree); };
  auto s_in_output_pixels = [&](double s, double half_angle, int resolution) {
    // s, in capture pixels, is in output pixels too: the capture's pixels are the output's
    // size unless the cap made them larger (then s is scaled up to output pixels).
    return s * 2 * std::tan(0.5 * fov_of(half_angle) * kDegree) / resolution / pixel_angle_;
  };
  for (std::size_t i = 0; i < n; ++i) {
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
    Outside& o = outside[i];
    o.object = version_for(i, nearest, &entry.source_faces);
    o.half_angle = to_centre > p.radius ? std::asin(p.radius / to_centre) : 85 * kDegree;
    o.resolution = capture_resolution(o.half_angle, pixel_angle_, cap);
    const double s = s_in_output_pixels(
        self_occluding_error(o.object, centre, corners, o.resolution, fov_of(o.half_angle)), o.half_angle, o.resolution);
    entry.self_occluding_error = static_cast<float>(s);
    entry.kind = s <= options_.ts_pixels ? LodKind::svmesh : LodKind::mvmesh;
    if (entry.kind == LodKind::svmesh) passing.push_back(i);
  }

  // Greedy clustering (Fig. 5): by decreasing projected area, each object joins, in order of
  // decreasing overlap, every cluster it can join while the union still passes the Ts test.
  std::vector<std::vector<std::size_t>> clusters;
  std::vector<std::vector<std::uint32_t>> cluster_faces;  // kept faces of merged members (empty: singleton)
  std::vector<Disc> disc(n);
  for (std::size_t i : passing) {
    const Vec3 to = placed_[i].centre - centre;
    disc[i] = {to / std::max(norm(to), 1e-300), outside[i].half_angle};
  }
  std::sort(passing.begin(), passing.end(), [&](std::size_t a, std::size_t b) {
    return disc[a].radius != disc[b].radius ? disc[a].radius > disc[b].radius : a < b;
  });
  for (std::size_t m : passing) {
    std::vector<std::size_t> current{m};
    std::vector<std::uint32_t> current_faces;
    if (options_.clustering) {
      std::vector<std::pair<double, std::size_t>> order;  // (overlap with m, cluster)
      for (std::size_t c = 0; c < clusters.size(); ++c) {
        double best = 0;
        for (std::size_t k : clusters[c]) best = std::max(best, overlap(disc[m], disc[k]));
        if (best > 0) order.push_back({-best, c});
      }
      std::sort(order.begin(), order.end());
      std::vector<std::size_t> absorbed;
      for (const auto& [negative, c] : order) {
        (void)negative;
        if (static_cast<int>(current.size() + clusters[c].size()) > options_.max_cluster) continue;
        std::vector<std::size_t> members = current;
        members.insert(members.end(), clusters[c].begin(), clusters[c].end());
        // The largest projection first: it holds the cluster's SVMesh.
        std::sort(members.begin(), members.end(), [&](std::size_t a, std::size_t b) {
          return disc[a].radius != disc[b].radius ? disc[a].radius > disc[b].radius : a < b;
        });
        std::vector<const Mesh*> parts;
        for (std::size_t k : members) parts.push_back(&outside[k].object);
        const Mesh u = merged(parts);
        const BoundingBox box = bounding_box(u);
        const double d = norm(box.center() - centre), r = 0.5 * box.diagonal();
        const double h = d > r ? std::asin(r / d) : 85 * kDegree;
        const int resolution = capture_resolution(h, pixel_angle_, cap);
        const std::vector<std::uint32_t> kept = seen_faces(u, centre, std::min(2 * resolution, 1024));
        const double s = s_in_output_pixels(self_occluding_error(u, kept, corners, resolution, fov_of(h)), h, resolution);
        if (s > options_.ts_pixels) continue;  // the union would show holes: not cluster-able
        current = std::move(members);
        current_faces = kept;
        absorbed.push_back(c);
      }
      std::sort(absorbed.rbegin(), absorbed.rend());
      for (std::size_t c : absorbed) {
        clusters.erase(clusters.begin() + static_cast<std::ptrdiff_t>(c));
        cluster_faces.erase(cluster_faces.begin() + static_cast<std::ptrdiff_t>(c));
      }
    }
    clusters.push_back(std::move(current));
    cluster_faces.push_back(std::move(current_faces));
  }

  // SVMeshes: one per cluster (a singleton is the paper's plain SVMesh).
  for (std::size_t c = 0; c < clusters.size(); ++c) {
    const std::vector<std::size_t>& members = clusters[c];
    const std::size_t holder = members.front();
    CellEntry& entry = out.entries[holder];
    if (members.size() == 1) {
      const Outside& o = outside[holder];
      const DepthImage depth = capture_depth(o.object, centre, o.resolution);
      entry.mesh = build_lod_mesh(o.object, {centre}, depth_variation_weights(o.object, depth), 1, tl);
      if (options_.textures)
        entry.textures.push_back(capture_texture(object_sets_[holder], centre, placed_[holder].centre,
                                                 placed_[holder].radius,
                                                 capture_resolution(o.half_angle, pixel_angle_,
                                                                    options_.max_texture_resolution)));
      continue;
    }
    std::vector<const Mesh*> parts;
    for (std::size_t k : members) parts.push_back(&outside[k].object);
    const Mesh u = merged(parts);
    std::vector<std::uint8_t> keep(u.num_faces(), 0);
    for (std::uint32_t f : cluster_faces[c]) keep[f] = 1;
    const Mesh seen = keep_faces(u, keep);  // what the centre sees of the cluster
    const BoundingBox box = bounding_box(u);
    const double d = norm(box.center() - centre), r = 0.5 * box.diagonal();
    const double h = d > r ? std::asin(r / d) : 85 * kDegree;
    const DepthImage depth = capture_depth(seen, centre, capture_resolution(h, pixel_angle_, cap));
    entry.mesh = build_lod_mesh(seen, {centre}, depth_variation_weights(seen, depth), 1, tl);
    for (std::size_t k : members) {
      entry.cluster.push_back(static_cast<std::uint32_t>(k));
      if (k == holder) continue;
      CellEntry& member = out.entries[k];
      member.kind = LodKind::in_cluster;
      member.cluster = {static_cast<std::uint32_t>(holder)};
    }
    if (options_.textures) {
      RenderSet whole;
      for (std::size_t k : members) whole.append(object_sets_[k]);
      entry.textures.push_back(capture_texture(whole, centre, box.center(), r,
                                               capture_resolution(h, pixel_angle_, options_.max_texture_resolution)));
    }
  }

  // MVMeshes.
  for (std::size_t i = 0; i < n; ++i) {
    CellEntry& entry = out.entries[i];
    if (entry.kind != LodKind::mvmesh) continue;
    const Placed& p = placed_[i];
    const Mesh& object = outside[i].object;
    std::vector<float> weights(object.num_vertices(), 0.0f);
    std::vector<Vec3> views{centre};
    for (const HexCell& nb : grid_.neighbours(cell)) views.push_back(grid_.eye_at_center(nb));
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
        entry.textures.push_back(capture_texture(object_sets_[i], eye, p.centre, p.radius,
                                                 capture_resolution(h, pixel_angle_, options_.max_texture_resolution)));
      }
    }
  }
  return out;
}

}  // namespace visimp
