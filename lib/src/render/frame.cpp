// The projection and worker pool every backend shares (see frame.h and renderer.h).
#include "visimp/render/frame.h"

#include <algorithm>
#include <cmath>

#include "visimp/core/bounding_box.h"
#include "visimp/core/errors.h"
#include "visimp/core/parallel.h"
#include "visimp/render/renderer.h"

namespace visimp {

double view_radius(const BoundingBox& box) { return box.diagonal() > 0 ? 0.5 * box.diagonal() * 1.01 : 1.0; }

RenderScene RenderScene::from_mesh(const Mesh& mesh, bool cull_back_faces) {
  const BoundingBox box = bounding_box(mesh);
  return from_mesh(mesh, cull_back_faces, box.center(), view_radius(box));
}

RenderScene RenderScene::from_mesh(const Mesh& mesh, bool cull_back_faces, const Vec3& center, double radius) {
  RenderScene scene;
  scene.radius = radius;
  scene.positions.reserve(mesh.positions.size());
  for (const Vec3& p : mesh.positions) {
    const Vec3 q = p - center;
    scene.positions.push_back({static_cast<float>(q.x), static_cast<float>(q.y), static_cast<float>(q.z)});
  }
  scene.faces = mesh.faces;
  scene.culled_faces = cull_back_faces ? scene.faces.size() : 0;
  return scene;
}

namespace {

// The cone around a unit axis whose normals are all within acos(min_cos) of it; the default
// (never skipped) for a cone of ~90° or more, which never lies wholly behind a camera.
NormalCone cone_around(const Vec3& axis, double min_cos) {
  NormalCone cone;
  if (min_cos <= 0.01) return cone;
  cone.axis = {static_cast<float>(axis.x), static_cast<float>(axis.y), static_cast<float>(axis.z)};
  // Margin: float normals, and screen-space culling of faces seen almost edge-on.
  cone.cutoff = static_cast<float>(-std::sqrt(1 - min_cos * min_cos) - 0.01);
  return cone;
}

// The cones of vertices [first, last) (see VertexCone) and of their runs of kClusterSize
// (`first` starts a run): every face is scanned, but only corners in the range are summed,
// in face order. A vertex's sums so never depend on how vertices are split among threads.
void vertex_range_cones(const RenderScene& scene, const std::vector<std::array<float, 3>>& unit_normals,
                        std::size_t first, std::size_t last, std::vector<VertexCone>& vertex_cones,
                        std::vector<NormalCone>& cluster_cones) {
  constexpr std::size_t kSize = RenderScene::kClusterSize;
  const std::vector<Face>& faces = scene.faces;
  const std::size_t culled_faces = scene.culled_faces;
  const std::size_t first_cluster = first / kSize, clusters = (last - first + kSize - 1) / kSize;
  std::vector<Vec3> axis(last - first), cluster_axis(clusters);
  std::vector<std::uint8_t> never(last - first, 0), cluster_never(clusters, 0);  // a face drawn from both sides
  auto in_range = [&](VertexIndex v) { return v >= first && v < last; };
  for (std::size_t t = 0; t < faces.size(); ++t) {
    const Vec3 n(unit_normals[t][0], unit_normals[t][1], unit_normals[t][2]);
    for (const VertexIndex v : faces[t]) {
      if (!in_range(v)) continue;
      axis[v - first] += n;
      cluster_axis[v / kSize - first_cluster] += n;
      if (t >= culled_faces) never[v - first] = cluster_never[v / kSize - first_cluster] = 1;
    }
  }
  for (Vec3& a : axis) {
    const double length = norm(a);
    if (length > 0) a = a / length;
  }
  for (Vec3& a : cluster_axis) {
    const double length = norm(a);
    a = length > 0 ? a / length : Vec3{};
  }
  std::vector<double> min_cos(last - first, 2.0);  // 2: no face with a normal (never facing)
  std::vector<double> cluster_min_cos(clusters, 1.0);
  for (std::size_t t = 0; t < faces.size(); ++t) {
    const Vec3 n(unit_normals[t][0], unit_normals[t][1], unit_normals[t][2]);
    if (squared_norm(n) == 0) continue;
    for (const VertexIndex v : faces[t]) {
      if (!in_range(v)) continue;
      double& m = min_cos[v - first];
      m = std::min(m, dot(axis[v - first], n));
      double& c = cluster_min_cos[v / kSize - first_cluster];
      c = std::min(c, dot(cluster_axis[v / kSize - first_cluster], n));
    }
  }
  auto pack = [](double x) { return static_cast<std::int8_t>(std::lround(std::clamp(x, -1.0, 1.0) * 127)); };
  for (std::size_t i = 0; i < last - first; ++i) {
    if (never[i] != 0) continue;
    if (min_cos[i] > 1.5) {  // only degenerate faces: always turned away
      vertex_cones[first + i].packed = {0, 0, 0, 1};
      continue;
    }
    if (min_cos[i] <= 0.01) continue;  // a cone of ~90° or more
    // Margins as for clusters, plus the axis's rounding to 1/127: < 0.014 on the dot product.
    const double cutoff = -std::sqrt(1 - min_cos[i] * min_cos[i]) - 0.01 - 0.014;
    vertex_cones[first + i].packed = {pack(axis[i].x), pack(axis[i].y), pack(axis[i].z),
                                      static_cast<std::int8_t>(std::max(-128.0, std::floor(cutoff * 127)))};
  }
  // A run of vertices: a cone around the normals of every face that uses one of them
  // (vertices are in order of first use by spatially ordered faces, so a run is a small
  // patch). Never set when one of those faces is drawn from both sides.
  for (std::size_t c = 0; c < clusters; ++c) {
    if (cluster_never[c] == 0 && squared_norm(cluster_axis[c]) > 0)
      cluster_cones[first_cluster + c] = cone_around(cluster_axis[c], cluster_min_cos[c]);
  }
}

}  // namespace

void RenderScene::compute_normal_cones(const std::vector<std::array<float, 3>>& unit_normals, unsigned threads) {
  clusters.assign((faces.size() + kClusterSize - 1) / kClusterSize, NormalCone{});
  const unsigned workers = worker_count(threads, faces.size() / (1 << 16) + 1);
  parallel_ranges(clusters.size(), 1 << 10, workers, [&](std::size_t begin, std::size_t end) {
    for (std::size_t c = begin; c < end; ++c) {
      const std::size_t first = c * kClusterSize, last = std::min(faces.size(), first + kClusterSize);
      if (last > culled_faces) continue;  // drawn from both sides: never all turned away
      Vec3 sum;
      for (std::size_t t = first; t < last; ++t) sum += Vec3(unit_normals[t][0], unit_normals[t][1], unit_normals[t][2]);
      const double length = norm(sum);
      if (length == 0) continue;
      const Vec3 axis = sum / length;
      double min_cos = 1;
      for (std::size_t t = first; t < last; ++t) {
        const Vec3 n(unit_normals[t][0], unit_normals[t][1], unit_normals[t][2]);
        if (squared_norm(n) > 0) min_cos = std::min(min_cos, dot(axis, n));
      }
      clusters[c] = cone_around(axis, min_cos);
    }
  });
  // One range of vertices per worker (whole runs of kClusterSize), each scanning every face.
  vertex_cones.assign(positions.size(), VertexCone{});
  vertex_clusters.assign((positions.size() + kClusterSize - 1) / kClusterSize, NormalCone{});
  const std::size_t runs = vertex_clusters.size(), runs_per_range = (runs + workers - 1) / std::max(1u, workers);
  parallel_ranges(runs, std::max<std::size_t>(runs_per_range, 1), workers, [&](std::size_t begin, std::size_t end) {
    vertex_range_cones(*this, unit_normals, begin * kClusterSize, std::min(positions.size(), end * kClusterSize),
                       vertex_cones, vertex_clusters);
  });
}

OrthoView OrthoView::looking_from(const Vec3& direction, double radius, int resolution) {
  OrthoView view;
  view.direction = direction / norm(direction);
  // Keep world +z up on screen unless the camera looks almost along z.
  const Vec3 helper = std::abs(view.direction.z) < 0.9 ? Vec3{0, 0, 1} : Vec3{0, 1, 0};
  const Vec3 up = helper - view.direction * dot(view.direction, helper);
  view.up = up / norm(up);
  view.right = cross(view.up, view.direction);
  view.radius = radius;
  view.resolution = resolution;
  return view;
}

void project_vertices(const RenderScene& scene, const OrthoView& view, std::vector<ScreenVertex>& out) {
  const double half = 0.5 * view.resolution;
  const double pixels_per_unit = half / view.radius;
  const float rx = static_cast<float>(view.right.x * pixels_per_unit);
  const float ry = static_cast<float>(view.right.y * pixels_per_unit);
  const float rz = static_cast<float>(view.right.z * pixels_per_unit);
  const float ux = static_cast<float>(view.up.x * pixels_per_unit);
  const float uy = static_cast<float>(view.up.y * pixels_per_unit);
  const float uz = static_cast<float>(view.up.z * pixels_per_unit);
  const double depth_per_unit = -0.5 / view.radius;
  const float dx = static_cast<float>(view.direction.x * depth_per_unit);
  const float dy = static_cast<float>(view.direction.y * depth_per_unit);
  const float dz = static_cast<float>(view.direction.z * depth_per_unit);
  const float offset = static_cast<float>(half);
  out.resize(scene.positions.size());
  for (std::size_t i = 0; i < scene.positions.size(); ++i) {
    const auto& p = scene.positions[i];
    out[i] = {rx * p[0] + ry * p[1] + rz * p[2] + offset, ux * p[0] + uy * p[1] + uz * p[2] + offset,
              dx * p[0] + dy * p[1] + dz * p[2] + 0.5f};
  }
}

void render_frames(const RenderScene& scene, const CameraSet& cameras, std::size_t first, std::size_t last,
                   const RenderOptions& options, FrameConsumer& consumer, RenderObserver* observer,
                   const std::function<void(unsigned workers)>& prepare,
                   const std::function<void(unsigned worker, Frame& frame)>& draw) {
  last = std::min(last, cameras.size());
  const unsigned workers = worker_count(options.threads, last > first ? last - first : 1);
  prepare(workers);
  consumer.begin(workers);
  std::vector<Frame> frames(workers);
  for_each_camera(first, last, workers, observer, [&](unsigned worker, std::size_t camera) {
    Frame& frame = frames[worker];
    frame.view = OrthoView::looking_from(cameras.directions[camera], scene.radius, options.resolution);
    draw(worker, frame);
    consumer.consume(frame, camera, worker);
  });
}

Frame render_view(Renderer& renderer, const RenderScene& scene, const Vec3& direction) {
  struct Capture final : FrameConsumer {
    Frame frame;
    void begin(unsigned) override {}
    void consume(const Frame& f, std::size_t, unsigned) override { frame = f; }
  } capture;
  const CameraSet one{"view", {direction / norm(direction)}};
  renderer.render(scene, one, 0, 1, capture);
  return std::move(capture.frame);
}

void check_render_options(const RenderOptions& options) {
  if (options.resolution < kMinResolution || options.resolution > kMaxResolution) {
    throw OptionError(&options.resolution, "RenderOptions::resolution",
                      "must be in " + std::to_string(kMinResolution) + ".." + std::to_string(kMaxResolution) +
                          ", got " + std::to_string(options.resolution));
  }
  if (options.threads > kMaxThreads)
    throw OptionError(&options.threads, "RenderOptions::threads", "must be at most " + std::to_string(kMaxThreads));
}

void for_each_camera(std::size_t first, std::size_t last, unsigned workers, RenderObserver* observer,
                     const std::function<void(unsigned worker, std::size_t camera)>& job) {
  std::function<void(double)> progress;
  if (observer != nullptr) progress = [observer](double done) { observer->on_render_progress(done); };
  parallel_for(first, last, workers, job, progress);
}

}  // namespace visimp
