// Embree 3 behind RayCaster (see ray_caster.h).
#include "visimp/render/ray_caster.h"

#include <embree3/rtcore.h>

#include <cmath>
#include <limits>
#include <string>

#include "visimp/core/errors.h"

namespace visimp {

struct RayCaster::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
};

RayCaster::RayCaster(const std::vector<std::array<float, 3>>& positions, const std::vector<Face>& faces,
                     unsigned threads)
    : impl_(std::make_unique<Impl>()) {
  const std::string config = threads > 0 ? "threads=" + std::to_string(threads) : "";
  impl_->device = rtcNewDevice(config.empty() ? nullptr : config.c_str());
  if (impl_->device == nullptr) throw BackendError("embree: could not create a device");
  impl_->scene = rtcNewScene(impl_->device);
  RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  // Embree may read 16 bytes from the last vertex; rtcSetNewGeometryBuffer pads, the extra
  // vertex (never indexed) keeps that true for any buffer we hand it.
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                        3 * sizeof(float), positions.size() + 1));
  for (std::size_t i = 0; i < positions.size(); ++i) {
    v[3 * i] = positions[i][0];
    v[3 * i + 1] = positions[i][1];
    v[3 * i + 2] = positions[i][2];
  }
  v[3 * positions.size()] = v[3 * positions.size() + 1] = v[3 * positions.size() + 2] = 0;
  auto* index = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), faces.size()));
  for (std::size_t f = 0; f < faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) index[3 * f + k] = faces[f][k];
  }
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);  // watertight: no ray slips between two faces
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(impl_->scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(impl_->scene);
  // Out of memory or a bad argument would otherwise read as "no hit" for every ray.
  const RTCError error = rtcGetDeviceError(impl_->device);
  if (error != RTC_ERROR_NONE) {
    rtcReleaseScene(impl_->scene);
    rtcReleaseDevice(impl_->device);
    throw BackendError("embree: building the ray-casting structure failed (error " +
                       std::to_string(static_cast<int>(error)) + ")");
  }
}

RayCaster::~RayCaster() {
  rtcReleaseScene(impl_->scene);
  rtcReleaseDevice(impl_->device);
}

namespace {

void set_ray(RTCRayHit& rh, const float* origin, const float* direction, float t_near, float t_far) {
  rh.ray.org_x = origin[0];
  rh.ray.org_y = origin[1];
  rh.ray.org_z = origin[2];
  rh.ray.dir_x = direction[0];
  rh.ray.dir_y = direction[1];
  rh.ray.dir_z = direction[2];
  rh.ray.tnear = t_near;
  rh.ray.tfar = t_far;
  rh.ray.time = 0;
  rh.ray.mask = 0xffffffffu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

}  // namespace

std::uint32_t RayCaster::first_hit(const std::array<float, 3>& origin, const std::array<float, 3>& direction,
                                   float t_near, float t_far) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  set_ray(rh, origin.data(), direction.data(), t_near, t_far);
  rtcIntersect1(impl_->scene, &context, &rh);
  return rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? kNoHit : rh.hit.primID;
}

void RayCaster::first_hits(const float* origins, const float* directions, std::size_t count, std::uint32_t* out) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;  // callers pass neighbouring rays together
  constexpr std::size_t kBatch = 64;
  RTCRayHit batch[kBatch];
  for (std::size_t first = 0; first < count; first += kBatch) {
    const std::size_t n = std::min(kBatch, count - first);
    for (std::size_t i = 0; i < n; ++i) {
      set_ray(batch[i], origins + 3 * (first + i), directions + 3 * (first + i), 0,
              std::numeric_limits<float>::infinity());
    }
    rtcIntersect1M(impl_->scene, &context, batch, static_cast<unsigned>(n), sizeof(RTCRayHit));
    for (std::size_t i = 0; i < n; ++i) {
      out[first + i] = batch[i].hit.geomID == RTC_INVALID_GEOMETRY_ID ? kNoHit : batch[i].hit.primID;
    }
  }
}

std::size_t RayCaster::crossings(const std::array<float, 3>& origin, const std::array<float, 3>& direction) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  std::size_t count = 0;
  float t = 0;
  // Bounded: a ray along a coplanar fan could otherwise step through many ties.
  for (int guard = 0; guard < 100000; ++guard) {
    RTCRayHit rh;
    set_ray(rh, origin.data(), direction.data(), t, std::numeric_limits<float>::infinity());
    rtcIntersect1(impl_->scene, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) break;
    ++count;
    t = std::nextafter(rh.ray.tfar, std::numeric_limits<float>::infinity()) * (1 + 1e-6f) + 1e-7f;
  }
  return count;
}

}  // namespace visimp
