// Resampling the visibility field for a viewpoint (Blais & Poulin Fig. 4): rays from the eye
// through 1 of every k pixels, each mapped to its slab's (u, v, s, t), and the cells of the
// samples there are marked. Casting the ray and intersecting it with both planes is the
// same as projecting the slab planes and walking their overlap, without the rasterizer.
//
// Post-filtering (§4.1): besides the nearest sample, mark the neighbouring samples' cells:
// the 2×2 around the ray in uv (uv), in st (st), or the 2×2×2×2 = 16 of both (uvst).
//
// The 4D mip-map (§8, proposed, not built by the paper): level ℓ halves all four sample
// counts, each coarse sample keeping the ids most frequent among its 16 children (weighted
// by rank). A viewer far from the st plane has query rays farther apart on it than one st
// sample; `mip` = auto then reads the level whose st spacing matches the rays'.
//
// Viewers inside the box: on a slab, rays start at the first start plane in front of the
// eye; cells between the eye and that plane (the gap) are marked when their box is in the
// view frustum. Conservative for the gap, exact beyond it up to sampling.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "visimp/field/field.h"
#include "visimp/render/perspective.h"

namespace visimp {

enum class Interpolation : std::uint8_t { None, Uv, St, UvSt };
std::string interpolation_name(Interpolation interpolation);
/// "none", "uv", "st", "uvst" (also "uv+st"); throws UsageError otherwise.
Interpolation parse_interpolation(const std::string& name);

struct ResampleOptions {
  int subsample = 4;  ///< 1 of `subsample` pixels (a square: a √k × √k stride), 1..1024
  Interpolation interpolation = Interpolation::None;
  int mip = 0;  ///< mip-map level to read; -1 = by the eye's distance (auto)
};

/// Throws OptionError for a subsample that is not a square in [1, 1024], or a level < −1.
void check_options(const ResampleOptions& options);
/// --subsample and --mip (the interpolation is the app's: it is a name).
std::vector<OptionSpec> describe_options(ResampleOptions& options);

struct ResampleResult {
  std::vector<std::uint8_t> marked;  ///< per cell
  std::size_t cells_marked = 0, rays = 0, rays_in_field = 0;
  std::size_t gap_cells = 0;  ///< cells marked because they lie between eye and start plane
  int mip_level = 0;          ///< level read (the deepest, when several slabs differ)
};

class FieldResampler {
 public:
  /// Keeps a reference to `field` (a temporary is refused); builds the mip-map levels.
  explicit FieldResampler(const VisibilityField& field);
  explicit FieldResampler(const VisibilityField&& field) = delete;

  /// `view` in mesh coordinates (eye, axes); its resolution is the image's.
  ResampleResult resample(const PerspectiveView& view, const ResampleOptions& options) const;
  /// Same, reusing `out`'s buffers (the per-frame path).
  void resample(const PerspectiveView& view, const ResampleOptions& options, ResampleResult& out) const;

  /// Levels available, the field itself included.
  int mip_levels() const { return static_cast<int>(levels_.size()) + 1; }
  /// The faces of the marked cells, ascending (input order).
  std::vector<std::uint32_t> faces_of(const std::vector<std::uint8_t>& marked) const;
  /// The same cell by cell (what a renderer walks; no sort): appended to `out`.
  void append_cell_faces(const std::vector<std::uint8_t>& marked, std::vector<std::uint32_t>& out) const;
  std::size_t face_count(const std::vector<std::uint8_t>& marked) const;

 private:
  using Samples = std::vector<std::uint32_t>;
  struct Level {
    int uv = 0, st = 0;
    std::vector<std::vector<Samples>> samples;  // [slab][layer]
  };
  const Samples& samples(int level, std::size_t slab, std::size_t layer) const;
  const VisibilityField& field_;
  std::vector<Level> levels_;  // levels 1.. (level 0 is the field's own samples)
  int slab_of_[3][2];          // slab index per (axis, side > 0), -1 when absent
};

}  // namespace visimp
