// Sampled distance between two surfaces (the core of Metro: Cignoni, Rocchini & Scopigno,
// "Metro: measuring error on simplified surfaces", 1998). Samples are the vertices plus
// area-uniform random points on the faces (fixed seed); each point's distance to the other
// surface is exact (CGAL AABB tree). Mean and RMS are area-weighted over the face samples;
// the maximum also covers the vertices. Results are identical for any thread count.
#pragma once

#include <cstddef>
#include <cstdint>

#include "visimp/core/mesh.h"

namespace visimp {

struct SurfaceDistanceOptions {
  /// Face samples per direction; 0 means 10 x the larger face count (Metro's default).
  std::size_t samples = 0;
  /// Seed of the sample positions; the same seed gives the same numbers.
  std::uint64_t seed = 1;
  /// Worker threads for the distance queries; 0 uses every core.
  int threads = 0;
};

/// Distances from the samples of one surface to the other, in input units.
struct DirectedDistance {
  double max = 0;   ///< one-sided Hausdorff distance (sampled)
  double mean = 0;  ///< area-weighted mean
  double rms = 0;   ///< area-weighted root mean square
  std::size_t samples = 0;
};

struct SurfaceDistance {
  DirectedDistance a_to_b, b_to_a;
  double hausdorff = 0;   ///< max of both directions
  double rms = 0;         ///< RMS over the samples of both directions, area-weighted
  double diagonal = 0;    ///< bounding-box diagonal of A: divide by it for relative numbers
  double seconds = 0;
};

/// Throws InvalidMeshError when either mesh has no non-degenerate face.
SurfaceDistance surface_distance(const Mesh& a, const Mesh& b, const SurfaceDistanceOptions& options = {});

}  // namespace visimp
