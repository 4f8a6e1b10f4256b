// Embree 3 ray casting for the reference visibility measure (see raycast_visibility.h).
#include "raycast_visibility.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "visimp/core/bounding_box.h"
#include "visimp/core/mesh_stats.h"
#include "visimp/core/orientation.h"
#include "visimp/core/parallel.h"
#include "visimp/render/frame.h"
#include "visimp/visibility/refine.h"

namespace visimp::reference {
namespace {

// Owns an Embree device and scene built from one mesh.
class EmbreeScene {
 public:
  EmbreeScene(const std::vector<Vec3>& positions, const std::vector<Face>& faces, const Vec3& center) {
    device_ = rtcNewDevice(nullptr);
    if (device_ == nullptr) throw std::runtime_error("embree: no device");
    scene_ = rtcNewScene(device_);
    RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), positions.size()));
    for (std::size_t i = 0; i < positions.size(); ++i) {
      const Vec3 p = positions[i] - center;
      v[3 * i] = static_cast<float>(p.x);
      v[3 * i + 1] = static_cast<float>(p.y);
      v[3 * i + 2] = static_cast<float>(p.z);
    }
    auto* index = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(unsigned), faces.size()));
    for (std::size_t f = 0; f < faces.size(); ++f) {
      for (int k = 0; k < 3; ++k) index[3 * f + k] = faces[f][k];
    }
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);  // watertight: no ray slips between two faces
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene_, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene_);
  }
  ~EmbreeScene() {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;
  RTCScene get() const { return scene_; }

 private:
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
};

struct SideSums {
  double seen = 0, total = 0;
};

}  // namespace

RaycastVisibility raycast_visibility(const Mesh& mesh, const CameraSet& cameras, const RaycastOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  RaycastVisibility out;
  const std::size_t input_faces = mesh.num_faces();
  const BoundingBox box = bounding_box(mesh);
  const double radius = view_radius(box);
  const Vec3 center = box.center();

  // Canonical winding: which side is outward on closed surfaces.
  const OrientationPatches patches = orientation_patches(mesh);
  Mesh wound{mesh.positions, {}, {}, {}};
  wound.faces.resize(input_faces);
  for (std::size_t f = 0; f < input_faces; ++f)
    wound.faces[f] = canonical_face(mesh.faces[f], patches.reversed[f] != 0);
  const auto refined = refine_long_edges(wound, options.max_edge_fraction * 2 * radius, 200'000'000);
  const Mesh& work = refined ? refined->mesh : wound;
  auto parent_of = [&](std::size_t t) { return refined ? refined->input_face[t] : t; };
  const std::size_t faces = work.num_faces();
  out.refined_faces = faces;

  std::vector<Vec3> normal(faces);
  std::vector<double> area(faces);
  for (std::size_t t = 0; t < faces; ++t) {
    const Vec3 n = face_normal_unnormalized(work, work.faces[t]);
    area[t] = 0.5 * norm(n);
    normal[t] = is_degenerate(work, work.faces[t]) ? Vec3{} : n / norm(n);
  }
  const EmbreeScene scene(work.positions, work.faces, center);

  const unsigned workers = worker_count(options.threads, cameras.size());
  std::vector<std::vector<SideSums>> front(workers, std::vector<SideSums>(faces));
  std::vector<std::vector<SideSums>> back(workers, std::vector<SideSums>(faces));
  std::vector<std::vector<std::uint32_t>> stamp(workers, std::vector<std::uint32_t>(faces, 0));
  std::vector<std::vector<std::uint8_t>> vertex_seen(workers, std::vector<std::uint8_t>(work.num_vertices(), 0));
  const int size = options.resolution;
  const double epsilon = options.vertex_epsilon * 2 * radius;

  parallel_for(0, cameras.size(), workers, [&](unsigned w, std::size_t c) {
    const OrthoView view = OrthoView::looking_from(cameras.directions[c], radius, size);
    const std::uint32_t frame = static_cast<std::uint32_t>(c + 1);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    const double start_distance = 2 * radius;  // the ray origins lie on a plane outside the sphere
    // Primary rays through every pixel centre.
    for (int j = 0; j < size; ++j) {
      for (int i = 0; i < size; ++i) {
        const double x = ((i + 0.5) * 2.0 / size - 1) * radius, y = ((j + 0.5) * 2.0 / size - 1) * radius;
        const Vec3 origin = view.right * x + view.up * y + view.direction * start_distance;
        RTCRayHit rh;
        rh.ray.org_x = static_cast<float>(origin.x);
        rh.ray.org_y = static_cast<float>(origin.y);
        rh.ray.org_z = static_cast<float>(origin.z);
        rh.ray.dir_x = static_cast<float>(-view.direction.x);
        rh.ray.dir_y = static_cast<float>(-view.direction.y);
        rh.ray.dir_z = static_cast<float>(-view.direction.z);
        rh.ray.tnear = 0;
        rh.ray.tfar = std::numeric_limits<float>::infinity();
        rh.ray.time = 0;
        rh.ray.mask = 0xffffffffu;
        rh.ray.id = 0;
        rh.ray.flags = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene.get(), &context, &rh);
        if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) stamp[w][rh.hit.primID] = frame;
      }
    }
    // The vertex rule: a shadow ray from the camera plane to each vertex.
    for (std::size_t i = 0; i < (options.vertex_rule ? work.num_vertices() : 0); ++i) {
      const Vec3 p = work.positions[i] - center;
      const double along = dot(p, view.direction);
      const Vec3 origin = p + view.direction * (start_distance - along);
      RTCRay ray;
      ray.org_x = static_cast<float>(origin.x);
      ray.org_y = static_cast<float>(origin.y);
      ray.org_z = static_cast<float>(origin.z);
      ray.dir_x = static_cast<float>(-view.direction.x);
      ray.dir_y = static_cast<float>(-view.direction.y);
      ray.dir_z = static_cast<float>(-view.direction.z);
      ray.tnear = 0;
      ray.tfar = static_cast<float>(start_distance - along - epsilon);
      ray.time = 0;
      ray.mask = 0xffffffffu;
      ray.id = 0;
      ray.flags = 0;
      rtcOccluded1(scene.get(), &context, &ray);
      vertex_seen[w][i] = ray.tfar >= 0 ? 1 : 0;  // tfar becomes -inf when something is in the way
    }
    for (std::size_t t = 0; t < faces; ++t) {
      const double cosine = dot(normal[t], view.direction);
      if (cosine == 0) continue;
      const Face& f = work.faces[t];
      const bool seen = stamp[w][t] == frame || vertex_seen[w][f[0]] || vertex_seen[w][f[1]] || vertex_seen[w][f[2]];
      SideSums& s = cosine > 0 ? front[w][t] : back[w][t];
      s.total += std::abs(cosine);
      if (seen) s.seen += std::abs(cosine);
    }
  });

  // Per side of every input face, the area-weighted mean of its sub-faces' V.
  std::vector<double> weighted[2] = {std::vector<double>(input_faces, 0), std::vector<double>(input_faces, 0)};
  std::vector<double> weight[2] = {std::vector<double>(input_faces, 0), std::vector<double>(input_faces, 0)};
  for (std::size_t t = 0; t < faces; ++t) {
    SideSums sides[2];
    for (unsigned w = 0; w < workers; ++w) {
      sides[0].seen += front[w][t].seen;
      sides[0].total += front[w][t].total;
      sides[1].seen += back[w][t].seen;
      sides[1].total += back[w][t].total;
    }
    const std::size_t parent = parent_of(t);
    for (int k = 0; k < 2; ++k) {
      if (sides[k].total <= 0) continue;
      const double a = std::max(area[t], 1e-300);
      weighted[k][parent] += a * sides[k].seen / sides[k].total;
      weight[k][parent] += a;
    }
  }
  out.face.assign(input_faces, 0.0f);
  double total_area = 0, visible = 0, hidden = 0;
  for (std::size_t f = 0; f < input_faces; ++f) {
    double side[2] = {0, 0};
    for (int k = 0; k < 2; ++k) side[k] = weight[k][f] > 0 ? weighted[k][f] / weight[k][f] : 0.0;
    const bool one_sided = patches.closed[patches.patch_of_face[f]] != 0;
    out.face[f] = static_cast<float>(one_sided ? side[0] : std::max(side[0], side[1]));
    const double a = 0.5 * norm(face_normal_unnormalized(mesh, mesh.faces[f]));
    total_area += a;
    visible += a * out.face[f];
    if (out.face[f] == 0) hidden += a;
  }
  out.mesh = total_area > 0 ? visible / total_area : 0;
  out.hidden_area_fraction = total_area > 0 ? hidden / total_area : 0;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

VisibilityAgreement compare_visibility(const Mesh& mesh, const std::vector<float>& v, const RaycastVisibility& ref) {
  VisibilityAgreement a;
  double total_area = 0, difference = 0, mesh_v = 0, hidden = 0, hidden_low = 0;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const double area = 0.5 * norm(face_normal_unnormalized(mesh, mesh.faces[f]));
    total_area += area;
    difference += area * std::abs(static_cast<double>(v[f]) - ref.face[f]);
    mesh_v += area * v[f];
    if (ref.face[f] == 0) {
      hidden += area;
      if (v[f] <= 0.02f) hidden_low += area;
    }
  }
  if (total_area > 0) {
    a.mean_abs_difference = difference / total_area;
    a.mesh_difference = mesh_v / total_area - ref.mesh;
  }
  a.hidden_area_low = hidden > 0 ? hidden_low / hidden : 1.0;
  return a;
}

}  // namespace visimp::reference
