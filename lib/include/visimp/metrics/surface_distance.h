// Sampled distance between two surfaces (the core of Metro: Cignoni, Rocchini & Scopigno,
// "Metro: measuring error on simplified surfaces", 1998). Samples are the vertices, points
// along the edges and area-uniform random points on the faces (fixed seed, one generator per
// face or edge); each point's distance to the other surface is exact (a bounding-volume
// hierarchy queried with the previous sample's answer as a hint). Samples are drawn and
// measured on the fly, in parallel; only their distances are kept. Mean, RMS and the histogram are
// area-weighted over the face samples only (Metro averages vertex, edge and face samples
// alike, which biases them toward dense regions); the maximum covers every sample.
// Degenerate faces carry no samples and no area. Results are identical for any thread count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "visimp/core/mesh.h"

namespace visimp {

enum class FaceSampling {
  random,      ///< independent area-uniform points (Monte Carlo)
  stratified,  ///< one jittered point in each cell of a regular k×k split of every face
};

struct SurfaceDistanceOptions {
  /// Face samples per direction; 0 means 10 x the larger face count (Metro's default).
  std::size_t samples = 0;
  /// Face samples per unit area (input units); when > 0 it replaces `samples`.
  double density = 0;
  FaceSampling sampling = FaceSampling::random;
  /// Seed of the sample positions; the same seed gives the same numbers.
  std::uint64_t seed = 1;
  /// Worker threads for the distance queries and the samples' spatial order; 0 uses every core.
  int threads = 0;
  /// Edge samples per direction, spread by length; 0 means one per face (Metro samples edges too).
  std::size_t edge_samples = 0;
  /// Histogram bins over [0, max] of each direction.
  std::size_t histogram_bins = 20;
  /// Non-empty: V per face of A (as SimplifyOptions::face_visibility), and A's samples are
  /// also summarised weighted by it, in `visible`. Passed explicitly, not read from A's face
  /// quality: a mesh's quality may mean anything.
  std::vector<float> face_visibility;
  /// Keep A's per-vertex and per-face distances to B (for error maps).
  bool vertex_errors = false;
};

/// Distances from the samples of one surface to the other, in input units.
struct DirectedDistance {
  double max = 0;                ///< one-sided Hausdorff distance (sampled)
  double mean = 0;               ///< area-weighted mean
  double rms = 0;                ///< area-weighted root mean square
  std::size_t samples = 0;       ///< all samples (vertex + edge + face)
  std::size_t face_samples = 0;  ///< those that carry area
  double area = 0;               ///< area of the sampled surface
  /// Share of the sampled area whose distance falls in bin i of [0, max] (sums to 1).
  std::vector<double> histogram;
};

/// A→B again, each face sample weighted by its area times V of its face in A.
struct VisibleDistance {
  double max = 0;  ///< over samples on faces with V > 0
  double mean = 0;
  double rms = 0;
  double visible_area = 0;  ///< Σ area·V
};

struct SurfaceDistance {
  DirectedDistance a_to_b, b_to_a;
  double hausdorff = 0;             ///< max of both directions
  double rms = 0;                   ///< RMS over the samples of both directions, area-weighted
  double diagonal = 0;              ///< bounding-box diagonal of A: divide by it for relative numbers
  VisibleDistance visible;          ///< when options.face_visibility is given
  std::vector<float> vertex_error;  ///< when options.vertex_errors: per vertex of A, input units
  std::vector<float> face_error;    ///< when options.vertex_errors: per face of A, the largest of its samples
  double seconds = 0;
  double seconds_sampling = 0, seconds_index = 0, seconds_queries = 0;
};

/// Throws InvalidMeshError when either mesh has no non-degenerate face, or when
/// face_visibility does not have one value per face of A, or a value outside [0, 1].
SurfaceDistance surface_distance(const Mesh& a, const Mesh& b, const SurfaceDistanceOptions& options = {});

/// A measured against many B (the levels of a compare): A's closest-triangle index, sample
/// plan and diagonal are made on the first call and kept, so each further call costs only
/// B's share. Every result equals surface_distance(a, b, options). A is referenced, not
/// copied: it must outlive this and stay unchanged. Calls may come from several threads
/// (they take turns).
class SurfaceDistanceReference {
 public:
  explicit SurfaceDistanceReference(const Mesh& a);
  ~SurfaceDistanceReference();
  SurfaceDistanceReference(const SurfaceDistanceReference&) = delete;
  SurfaceDistanceReference& operator=(const SurfaceDistanceReference&) = delete;

  SurfaceDistance distance_to(const Mesh& b, const SurfaceDistanceOptions& options = {}) const;

  struct Cache;  // private to surface_distance.cpp

 private:
  const Mesh& a_;
  std::unique_ptr<Cache> cache_;
};

}  // namespace visimp
