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

// Per vertex: the cone of the normals of its faces (see VertexCone).
std::vector<VertexCone> vertex_normal_cones(const RenderScene& scene,
                                            const std::vector<std::array<float, 3>>& unit_normals) {
  const std::vector<Face>& faces = scene.faces;
  const std::size_t culled_faces = scene.culled_faces;
  const std::size_t vertices = scene.positions.size();
  std::vector<Vec3> axis(vertices);
  std::vector<std::uint8_t> never(vertices, 0);  // has a face drawn from both sides
  for (std::size_t t = 0; t < faces.size(); ++t) {
    for (const VertexIndex v : faces[t]) {
      axis[v] += Vec3(unit_normals[t][0], unit_normals[t][1], unit_normals[t][2]);
      if (t >= culled_faces) never[v] = 1;
    }
  }
  for (Vec3& a : axis) {
    const double length = norm(a);
    if (length > 0) a = a / length;
  }
  std::vector<double> min_cos(vertices, 2.0);  // 2: no face with a normal (never facing)
  for (std::size_t t = 0; t < faces.size(); ++t) {
    const Vec3 n(unit_normals[t][0], unit_normals[t][1], unit_normals[t][2]);
    if (squared_norm(n) == 0) continue;
    for (const VertexIndex v : faces[t]) min_cos[v] = std::min(min_cos[v], dot(axis[v], n));
  }
  std::vector<VertexCone> vertex_cones(vertices);
  auto pack = [](double x) { return static_cast<std::int8_t>(std::lround(std::clamp(x, -1.0, 1.0) * 127)); };
  for (std::size_t v = 0; v < vertices; ++v) {
    if (never[v] != 0) continue;
    if (min_cos[v] > 1.5) {  // only degenerate faces: always turned away
      vertex_cones[v].packed = {0, 0, 0, 1};
      continue;
    }
    if (min_cos[v] <= 0.01) continue;  // a cone of ~90° or more
    // Margins as for clusters, plus the axis's rounding to 1/127: < 0.014 on the dot product.
    const double cutoff = -std::sqrt(1 - min_cos[v] * min_cos[v]) - 0.01 - 0.014;
    vertex_cones[v].packed = {pack(axis[v].x), pack(axis[v].y), pack(axis[v].z),
                              static_cast<std::int8_t>(std::max(-128.0, std::floor(cutoff * 127)))};
  }
  return vertex_cones;
}

// Per run of kClusterSize consecutive vertices: a cone around the normals of every face that
// uses one of them (vertices are in order of first use by spatially ordered faces, so a run
// is a small patch). Never set when one of those faces is drawn from both sides.
std::vector<NormalCone> vertex_cluster_cones(const RenderScene& scene,
                                             const std::vector<std::array<float, 3>>& unit_normals) {
  constexpr std::size_t kSize = RenderScene::kClusterSize;
  const std::size_t clusters = (scene.positions.size() + kSize - 1) / kSize;
  std::vector<Vec3> sum(clusters);
  std::vector<std::uint8_t> never(clusters, 0);
  for (std::size_t t = 0; t < scene.faces.size(); ++t) {
    const Vec3 n(unit_normals[t][0], unit_normals[t][1], unit_normals[t][2]);
    for (const VertexIndex v : scene.faces[t]) {
      sum[v / kSize] += n;
      if (t >= scene.culled_faces) never[v / kSize] = 1;
    }
  }
  std::vector<double> min_cos(clusters, 1.0);
  for (Vec3& a : sum) {
    const double length = norm(a);
    a = length > 0 ? a / length : Vec3{};
  }
  for (std::size_t t = 0; t < scene.faces.size(); ++t) {
    const Vec3 n(unit_normals[t][0], unit_normals[t][1], unit_normals[t][2]);
    if (squared_norm(n) == 0) continue;
    for (const VertexIndex v : scene.faces[t]) min_cos[v / kSize] = std::min(min_cos[v / kSize], dot(sum[v / kSize], n));
  }
  std::vector<NormalCone> cones(clusters);
  for (std::size_t c = 0; c < clusters; ++c) {
    if (never[c] == 0 && squared_norm(sum[c]) > 0) cones[c] = cone_around(sum[c], min_cos[c]);
  }
  return cones;
}

}  // namespace

void RenderScene::compute_normal_cones(const std::vector<std::array<float, 3>>& unit_normals) {
  clusters.assign((faces.size() + kClusterSize - 1) / kClusterSize, NormalCone{});
  for (std::size_t c = 0; c < clusters.size(); ++c) {
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
  vertex_cones = vertex_normal_cones(*this, unit_normals);
  vertex_clusters = vertex_cluster_cones(*this, unit_normals);
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
