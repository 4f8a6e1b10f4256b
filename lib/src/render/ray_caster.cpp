// Embree 3 behind RayCaster (see ray_caster.h). libembree3 (and TBB behind it) is opened when
// the first RayCaster is built, not linked (core/shared_library.h): only the visibility field
// casts rays, and linking it cost every visimp process ~6 ms of start-up. The header gives the
// types and prototypes; nothing links libembree3, so a call that bypasses the table below is an
// undefined symbol (the apps and tests fail to link).
#include "visimp/render/ray_caster.h"

#include <embree3/rtcore.h>

#include <cmath>
#include <limits>
#include <string>

#include "../core/shared_library.h"
#include "visimp/core/errors.h"

#ifndef VISIMP_EMBREE_LIBRARY
#define VISIMP_EMBREE_LIBRARY "libembree3.so.3"  // CMake sets the soname of the one found
#endif

namespace visimp {
namespace {

// Every Embree entry point used here, by its name without "rtc" (rtcInitIntersectContext is
// inline in the header).
#define VISIMP_EMBREE_FUNCTIONS(X) \
  X(AttachGeometry)                \
  X(CommitGeometry)                \
  X(CommitScene)                   \
  X(GetDeviceError)                \
  X(Intersect1)                    \
  X(Intersect1M)                   \
  X(NewDevice)                     \
  X(NewGeometry)                   \
  X(NewScene)                      \
  X(ReleaseDevice)                 \
  X(ReleaseGeometry)               \
  X(ReleaseScene)                  \
  X(SetNewGeometryBuffer)          \
  X(SetSceneFlags)

struct EmbreeApi {
#define VISIMP_EMBREE_MEMBER(name) decltype(&::rtc##name) name = nullptr;
  VISIMP_EMBREE_FUNCTIONS(VISIMP_EMBREE_MEMBER)
#undef VISIMP_EMBREE_MEMBER
};

EmbreeApi load_embree() {
  try {
    const detail::SharedLibrary library(VISIMP_EMBREE_LIBRARY, "libembree3-3");
    EmbreeApi api;
#define VISIMP_EMBREE_RESOLVE(name) library.resolve("rtc" #name, api.name);
    VISIMP_EMBREE_FUNCTIONS(VISIMP_EMBREE_RESOLVE)
#undef VISIMP_EMBREE_RESOLVE
    return api;
  } catch (const BackendError& e) {
    throw BackendError(std::string("embree: ") + e.what());
  }
}

// Loads on the first call; a failed load throws and is tried again on the next call.
const EmbreeApi& embree() {
  static const EmbreeApi api = load_embree();
  return api;
}

}  // namespace

struct RayCaster::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
};

RayCaster::RayCaster(const std::vector<std::array<float, 3>>& positions, const std::vector<Face>& faces,
                     unsigned threads)
    : impl_(std::make_unique<Impl>()) {
  const EmbreeApi& rtc = embree();
  const std::string config = threads > 0 ? "threads=" + std::to_string(threads) : "";
  impl_->device = rtc.NewDevice(config.empty() ? nullptr : config.c_str());
  if (impl_->device == nullptr) throw BackendError("embree: could not create a device");
  impl_->scene = rtc.NewScene(impl_->device);
  RTCGeometry geometry = rtc.NewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  // Embree may read 16 bytes from the last vertex; rtcSetNewGeometryBuffer pads, the extra
  // vertex (never indexed) keeps that true for any buffer we hand it.
  auto* v = static_cast<float*>(rtc.SetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                         3 * sizeof(float), positions.size() + 1));
  for (std::size_t i = 0; i < positions.size(); ++i) {
    v[3 * i] = positions[i][0];
    v[3 * i + 1] = positions[i][1];
    v[3 * i + 2] = positions[i][2];
  }
  v[3 * positions.size()] = v[3 * positions.size() + 1] = v[3 * positions.size() + 2] = 0;
  auto* index = static_cast<unsigned*>(rtc.SetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                3 * sizeof(unsigned), faces.size()));
  for (std::size_t f = 0; f < faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) index[3 * f + k] = faces[f][k];
  }
  rtc.SetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);  // watertight: no ray slips between two faces
  rtc.CommitGeometry(geometry);
  rtc.AttachGeometry(impl_->scene, geometry);
  rtc.ReleaseGeometry(geometry);
  rtc.CommitScene(impl_->scene);
  // Out of memory or a bad argument would otherwise read as "no hit" for every ray.
  const RTCError error = rtc.GetDeviceError(impl_->device);
  if (error != RTC_ERROR_NONE) {
    rtc.ReleaseScene(impl_->scene);
    rtc.ReleaseDevice(impl_->device);
    throw BackendError("embree: building the ray-casting structure failed (error " +
                       std::to_string(static_cast<int>(error)) + ")");
  }
}

RayCaster::~RayCaster() {
  const EmbreeApi& rtc = embree();
  rtc.ReleaseScene(impl_->scene);
  rtc.ReleaseDevice(impl_->device);
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
  const EmbreeApi& rtc = embree();
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  set_ray(rh, origin.data(), direction.data(), t_near, t_far);
  rtc.Intersect1(impl_->scene, &context, &rh);
  return rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? kNoHit : rh.hit.primID;
}

void RayCaster::first_hits(const float* origins, const float* directions, std::size_t count, std::uint32_t* out) const {
  const EmbreeApi& rtc = embree();
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
    rtc.Intersect1M(impl_->scene, &context, batch, static_cast<unsigned>(n), sizeof(RTCRayHit));
    for (std::size_t i = 0; i < n; ++i) {
      out[first + i] = batch[i].hit.geomID == RTC_INVALID_GEOMETRY_ID ? kNoHit : batch[i].hit.primID;
    }
  }
}

std::size_t RayCaster::crossings(const std::array<float, 3>& origin, const std::array<float, 3>& direction) const {
  const EmbreeApi& rtc = embree();
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  std::size_t count = 0;
  float t = 0;
  // Bounded: a ray along a coplanar fan could otherwise step through many ties.
  for (int guard = 0; guard < 100000; ++guard) {
    RTCRayHit rh;
    set_ray(rh, origin.data(), direction.data(), t, std::numeric_limits<float>::infinity());
    rtc.Intersect1(impl_->scene, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) break;
    ++count;
    t = std::nextafter(rh.ray.tfar, std::numeric_limits<float>::infinity()) * (1 + 1e-6f) + 1e-7f;
  }
  return count;
}

}  // namespace visimp
