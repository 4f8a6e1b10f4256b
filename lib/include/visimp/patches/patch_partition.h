// Polygonal patches (Meruvia Pastor, "Visibility Preprocessing Using Spherical Sampling of
// Polygonal Patches", §3.1): connected groups of faces that are drawn, sampled and culled
// as one unit, so view reconstruction costs one bit per patch instead of one per face.
//
// Every face starts as its own patch; faces sharing an edge are neighbours (all faces
// around a non-manifold edge are mutual neighbours). Repeatedly the smallest patch by area
// (ties: lowest id) is fused with the neighbour that gives the smallest bounding-box
// diagonal of the fused patch (ties: the smaller neighbour diagonal, then the lowest id),
// so patches grow compactly. It stops at the requested count, or when no patch can fuse
// any more: a patch whose every fusion would exceed `max_diagonal`, and a patch without
// neighbours (a separate component), are left as they are.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "visimp/core/mesh.h"
#include "visimp/core/option_table.h"

namespace visimp {

struct PatchOptions {
  std::size_t count = 1000;  ///< stop at this many patches; 0 = no count limit (max_diagonal must be set)
  double max_diagonal = 0;   ///< > 0: never make a patch with a longer bounding-box diagonal (input units)
};

std::vector<OptionSpec> describe_options(PatchOptions& options);
/// Throws UsageError when neither a count nor a diagonal limit is set, or the limit is negative.
void check_options(const PatchOptions& options);

struct PatchPartition {
  /// Patch of every face. Patches are numbered by their lowest face index.
  std::vector<std::uint32_t> face_patch;
  std::vector<double> area;               ///< per patch
  std::vector<double> diagonal;           ///< per patch: its vertices' bounding-box diagonal
  std::vector<std::uint32_t> face_count;  ///< per patch
  std::size_t components = 0;             ///< edge-connected components of the mesh (a lower bound on the count)
  double seconds = 0;

  std::size_t patch_count() const { return area.size(); }
};

/// For every face, the faces sharing an edge with it (all of them around a non-manifold
/// edge, a star through the first beyond 16), possibly repeated.
std::vector<std::vector<std::uint32_t>> face_neighbours(const Mesh& mesh);

/// Deterministic: the same mesh and options give the same partition on any machine.
PatchPartition build_patches(const Mesh& mesh, const PatchOptions& options);

/// One patch per face (the ID-bitfields of Meruvia Pastor & Strothotte).
PatchPartition faces_as_patches(const Mesh& mesh);

/// Colours far apart in hue for consecutive patch numbers (golden-ratio hue steps), so
/// neighbouring patches differ in a picture.
std::vector<std::array<std::uint8_t, 3>> patch_colors(std::size_t patches);

}  // namespace visimp
