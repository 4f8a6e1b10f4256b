// Mergeable visibility tallies. Per refined face t and a range of cameras v:
//
//     seen(t)  = Σ_v F(t, v) · q(R(v)·N(t))      total(t) = Σ_v q(R(v)·N(t))
//
// with q(w) = round(65535 · max(0, w)), so V(t) = seen / total (Zhang & Turk 2002, eq. 4.3;
// every camera stands for the same area of the sphere). Faces drawn from both sides (those
// at or past key.one_sided_faces: not on a closed outward surface) also carry the same sums
// for their back side, with q(−R·N): seen_back and total_back, indexed from one_sided_faces. The sums are integers:
// adding slices in any order, on any number of threads, processes or machines gives the same bits. A camera set has at
// most 65536 cameras, so a uint32 sum cannot overflow.
//
// File format (little-endian): "VISIMPT2", then the header fields in declaration order,
// the camera ranges, seen[faces], total[faces], seen_back[faces − one_sided_faces],
// total_back[faces − one_sided_faces] (all uint32).
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace visimp {

/// Everything that must match for two tallies to be added.
struct TallyKey {
  static constexpr std::uint32_t kFractional = 1;    ///< flags: F is fractional
  static constexpr std::uint32_t kDepthTest = 2;     ///< flags: the depth-tolerance test was on
  static constexpr std::uint32_t kNoRefine = 4;      ///< flags: long edges were not split
  static constexpr std::uint32_t kTrustWinding = 8;  ///< flags: one-sided F on the input's winding

  std::uint64_t mesh_hash = 0;        ///< of the input mesh's positions and faces
  std::uint64_t camera_hash = 0;      ///< of the camera directions
  std::uint64_t camera_count = 0;     ///< cameras in the whole set
  std::uint64_t faces = 0;            ///< refined faces
  std::uint64_t one_sided_faces = 0;  ///< the first faces, on closed outward surfaces: front side only
  std::uint32_t resolution = 0;
  std::uint32_t flags = 0;  ///< bit 0: fractional F, 1: depth test, 2: no refinement, 3: trust winding
  double worst_view_cosine = 0;
  double depth_tolerance_pixels = 0;

  bool operator==(const TallyKey& o) const;
  bool operator!=(const TallyKey& o) const { return !(*this == o); }
};

struct VisibilityTally {
  static constexpr std::uint32_t kMaxWeight = 65535;
  static constexpr std::size_t kMaxCameras = 65536;

  TallyKey key;
  std::vector<std::pair<std::uint64_t, std::uint64_t>> camera_ranges;  ///< [first, last), sorted, disjoint
  std::vector<std::uint32_t> seen, total;                              ///< per face, front side
  std::vector<std::uint32_t> seen_back, total_back;                    ///< per face from one_sided_faces on, back side

  /// Zeroed sums for the key's faces.
  void reset_sums();

  /// Adds `other`; throws UsageError if the keys differ or camera ranges overlap.
  void merge(const VisibilityTally& other);
  /// True when the ranges cover every camera of the set.
  bool complete() const;
  /// "0..129, 200..258"
  std::string describe_ranges() const;
  /// The cameras no range covers, in the same notation ("none" when complete).
  std::string describe_missing() const;

  /// Atomic write; throws IoError.
  void write(const std::string& path) const;
  /// What write() writes (parse() reads it back): for sending a tally between processes.
  std::string bytes() const;
  /// Throws IoError naming the file for a wrong magic, truncation or inconsistent sizes.
  static VisibilityTally read(const std::string& path);
  /// The same from bytes in memory; `path` names them in errors.
  static VisibilityTally parse(const std::string& bytes, const std::string& path);
};

/// Quantised camera weight q(w) (see above), for w in [-1, 1].
/// The clamp at zero comes after a signed conversion (for w < 0 the rounded value truncates to
/// at most 0: the same integer as clamping first). A float compare-and-select would become a
/// branch or keep the tally loops scalar (it may trap); an integer one does neither.
inline std::uint32_t quantize_weight(float w) {
  const auto q = static_cast<std::int32_t>(w * static_cast<float>(VisibilityTally::kMaxWeight) + 0.5f);
  return static_cast<std::uint32_t>(q < 0 ? 0 : q);
}

}  // namespace visimp
