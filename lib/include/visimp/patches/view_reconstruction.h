// View reconstruction (Meruvia Pastor §3.3–3.4; Meruvia Pastor & Strothotte §3.2): for a
// viewpoint on or outside the sampling sphere, OR the bitfields of the samples that
// surround its direction (SampleSelector) and draw the units whose bit is set. Not
// conservative: a face seen from the viewpoint but from none of those samples is missed.
#pragma once

#include <cstdint>
#include <vector>

#include "visimp/patches/bitfield_file.h"
#include "visimp/patches/sample_selection.h"

namespace visimp {

class ViewReconstructor {
 public:
  /// With `precompute_cells`, the joined row of every cell is computed up front (the
  /// ID-bitfield paper's per-hull-face lists): a query is then a lookup.
  /// Keeps a reference to `set`, which must outlive the reconstructor (a temporary is refused).
  explicit ViewReconstructor(const BitfieldSet& set, bool precompute_cells = false);
  explicit ViewReconstructor(const BitfieldSet&& set, bool precompute_cells = false) = delete;

  const SampleSelector& selector() const { return selector_; }
  std::size_t words_per_row() const { return set_.bits.words_per_row; }

  /// Direction from the sampling-sphere centre to a viewpoint in mesh coordinates (the
  /// centre's own direction when the viewpoint is the centre: +z).
  Vec3 direction_to(const Vec3& viewpoint) const;
  /// True when `viewpoint` is strictly inside the sampling sphere, where reconstruction
  /// may miss more (the papers' "closer than the samples" case).
  bool inside_sphere(const Vec3& viewpoint) const;

  /// ORs the rows of the samples around `direction` into `out` (words_per_row() words).
  void join(const Vec3& direction, std::uint64_t* out) const;
  /// The units (patches or faces) to draw, ascending.
  std::vector<std::uint32_t> units(const Vec3& direction) const;
  /// The faces of the units to draw, ascending.
  std::vector<std::uint32_t> faces(const Vec3& direction) const;
  /// Faces in the units set in a joined row.
  std::size_t face_count(const std::uint64_t* joined) const;

 private:
  const BitfieldSet& set_;
  SampleSelector selector_;
  std::vector<std::uint64_t> cell_rows_;          // precomputed: cells × words
  std::vector<std::uint32_t> unit_face_offsets_;  // CSR of the faces of each unit
  std::vector<std::uint32_t> unit_faces_;
};

}  // namespace visimp
