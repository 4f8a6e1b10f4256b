// First-hit ray casting on the CPU (Embree 3, a Debian package): what the visibility field
// samples its lines with and what "visibility tracing" casts at render time. Its own target,
// visimp_render_embree, like the OSMesa backend: nothing else links Embree.
//
// Positions are taken relative to a centre in float, as RenderScene does, so a mesh far
// from the origin keeps its precision. Rays are given in the same relative frame.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "visimp/core/mesh.h"

namespace visimp {

class RayCaster {
 public:
  static constexpr std::uint32_t kNoHit = 0xffffffffu;

  /// Builds the acceleration structure over `faces` (degenerate faces are never hit) with
  /// `threads` threads (0 = Embree's default, one per hardware thread). Throws BackendError
  /// when Embree fails (out of memory, for one).
  RayCaster(const std::vector<std::array<float, 3>>& positions, const std::vector<Face>& faces, unsigned threads = 0);
  ~RayCaster();
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;

  /// The face first hit by origin + t·direction for t in (t_near, t_far), or kNoHit.
  /// Safe to call from many threads at once.
  std::uint32_t first_hit(const std::array<float, 3>& origin, const std::array<float, 3>& direction, float t_near = 0,
                          float t_far = 1e30f) const;
  /// Casts `count` rays at once (origins and directions packed xyz); writes first hits.
  void first_hits(const float* origins, const float* directions, std::size_t count, std::uint32_t* out) const;
  /// How many surfaces the ray crosses for t > 0 (parity tells inside from outside).
  std::size_t crossings(const std::array<float, 3>& origin, const std::array<float, 3>& direction) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace visimp
