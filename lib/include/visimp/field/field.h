// The visibility field (Blais & Poulin, "Sampling Visibility in Three-Space"): for every
// line of a two-plane parameterisation ("slab"), the cells a viewer looking along it sees.
//
// Slab placement (the paper leaves it open, §7.4). A slab belongs to a side of the scene's
// box: axis a and the side σ the viewer is on; its lines travel toward −σ along a.
//   - The uv plane is at infinity (as in the paper's Fig. 13 set-up): (u, v) are the
//     line's slopes along the two other axes per unit travelled along a, both in [−1, 1].
//     Six slabs then split the directions like a cube map: every direction belongs to the
//     slab of its dominant axis.
//   - The st plane cuts the box through its centre, across a. Its rectangle is the box's
//     cross-section widened by half the box's depth along a on each side: exactly the lines
//     of slope ≤ 1 that pass through the box cross it there.
// So six slabs hold every line through the box in both directions: any viewpoint outside
// the box has all of its rays into the box in some slab. `--slabs 1` keeps only the +z
// slab, the paper's single slab (views from the +z side, within 45° per axis).
//
// A sample stores what a line shows from where it enters the box (the start plane, layer
// 0). For viewers inside the box, `layers` > 1 adds start planes inside it, evenly spaced;
// a viewer uses the nearest plane in front of it and marks the cells in the gap between
// (conservative: see resample.h).
//
// Pre-filtering (§3.3): each (u, v, s, t) sample casts 3×3 × 3×3 = 81 rays through its uv
// and st cells and keeps the `ids` cell ids hit most often, ties to the smaller id; unused
// entries are null.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "visimp/core/bounding_box.h"
#include "visimp/core/mesh.h"
#include "visimp/core/option_table.h"
#include "visimp/field/cells.h"

namespace visimp {

struct FieldOptions {
  CellOptions cells;
  int uv = 16;              ///< uv samples per side, 2..64
  int st = 16;              ///< st samples per side, 2..64
  int ids = 1;              ///< cell ids kept per sample, 1..8
  int slabs = 6;            ///< 6 (one per side of the box) or 1 (the +z slab, the paper's set-up)
  int layers = 1;           ///< start planes per slab (1: the box's side only), 1..16
  std::size_t threads = 0;  ///< 0 = one per hardware thread
};

inline constexpr int kMinSamples = 2, kMaxSamples = 64, kMaxIds = 8, kMaxLayers = 16;

/// Throws OptionError naming the field out of range.
void check_options(const FieldOptions& options, std::size_t faces);
/// --grid, --uv, --st, --ids, --slabs, --layers, --threads (the cell mode is the app's).
std::vector<OptionSpec> describe_options(FieldOptions& options);

/// One slab's geometry (see the file comment).
struct Slab {
  int axis = 2;                     ///< a: 0 = x, 1 = y, 2 = z
  int side = 1;                     ///< σ: +1 viewer on the max side (lines travel −a), −1 the min side
  double plane = 0;                 ///< coordinate along a of the st plane (the box's centre)
  std::array<double, 2> s_range{};  ///< st rectangle along the first other axis
  std::array<double, 2> t_range{};  ///< and the second
  std::vector<double> starts;       ///< start planes along a, layer 0 = the box's side

  /// The two other axes, in (s, t) order: (a+1) mod 3, (a+2) mod 3.
  int s_axis() const { return (axis + 1) % 3; }
  int t_axis() const { return (axis + 2) % 3; }
  /// The direction of a line of slopes (u, v) (not normalised: |component along a| = 1).
  Vec3 direction(double u, double v) const;
};

/// Six (or one) slabs for a box, `layers` start planes each.
std::vector<Slab> place_slabs(const BoundingBox& box, int slabs, int layers);

struct VisibilityField {
  std::uint64_t mesh_hash = 0;
  std::size_t faces = 0, vertices = 0;
  FieldOptions options;  ///< as built (cells.face_objects is not kept)
  BoundingBox box;
  CellPartition cells;
  std::vector<Slab> slabs;
  /// Per slab and layer: uv·uv·st·st·ids entries, index ((((iu·uv + iv)·st + is)·st + it)·ids + rank);
  /// an entry is a cell id + 1, 0 = null.
  std::vector<std::vector<std::vector<std::uint32_t>>> samples;
  /// Solid interior: 1 bit per voxel of a kOccupancy³ grid over the box, set when a point
  /// there is inside closed geometry (ray parity, majority of 6 axis rays).
  static constexpr int kOccupancy = 32;
  std::vector<std::uint8_t> interior;
  double seconds_build = 0;
  std::uint64_t rays = 0;

  std::size_t samples_per_layer() const {
    const std::size_t uv = static_cast<std::size_t>(options.uv), st = static_cast<std::size_t>(options.st);
    return uv * uv * st * st;
  }
  /// Bytes the samples take at their stored width (2 bytes when ids fit, else 4).
  std::size_t sample_bytes() const;
  int id_width() const { return cells.num_cells() < 0xffff ? 2 : 4; }
  /// True when `p` (mesh coordinates) is in a voxel marked as solid interior.
  bool inside_solid(const Vec3& p) const;
};

class RenderObserver;

/// Builds the field for a mesh: cells, slabs, 81 rays per sample (Embree). Throws
/// OptionError for options out of range, InvalidMeshError for a mesh without faces.
VisibilityField build_field(const Mesh& mesh, const FieldOptions& options, RenderObserver* observer = nullptr);

/// Ranks the ids of one sample's rays (§3.3): the `keep` most frequent, ties to the smaller;
/// `hits` may contain kNoCell (missed rays), which is never kept. Writes id + 1 (0 = null).
inline constexpr std::uint32_t kNoCell = 0xffffffffu;
void rank_cells(std::vector<std::uint32_t>& hits, int keep, std::uint32_t* out);

/// The .vfd file (docs/field.md): header, cells, per-face cell, run-length coded samples.
struct FieldFileSizes {
  std::size_t file_bytes = 0, raw_sample_bytes = 0, coded_sample_bytes = 0;
  double compression_ratio() const {
    return coded_sample_bytes ? static_cast<double>(raw_sample_bytes) / static_cast<double>(coded_sample_bytes) : 1;
  }
};
FieldFileSizes write_field_file(const VisibilityField& field, const std::string& path);
/// Throws IoError naming the file and the problem (truncation, bad sizes, unknown version).
VisibilityField read_field_file(const std::string& path);
/// The same from bytes in memory (`path` only names them in messages).
VisibilityField parse_field_file(const std::string& bytes, const std::string& path);
/// The run-length code of the samples alone, without writing a file.
FieldFileSizes measure_field_coding(const VisibilityField& field);

/// Throws IoError when the field was built for another mesh (content hash).
void check_field_matches(const VisibilityField& field, const Mesh& mesh, const std::string& field_path,
                         const std::string& mesh_path);

}  // namespace visimp
