// Edge-collapse simplification with quadric error metrics (Garland & Heckbert 1997), the
// engine behind both of visimp's methods:
//   QB — plain quadrics order the queue and place the new vertex;
//   VG — visibility-weighted quadrics Q_v = Σ V(t)² K_t order the queue (Zhang & Turk 2002
//        eq. 5.8–5.10), the plain ones still place the vertex and give the error. Each
//        input face's V is fixed; a vertex's Q_v is the sum over the input faces merged into
//        it, exactly like Q, so weights follow the input faces through every collapse.
//        With V ≡ 1 VG is QB bit for bit.
//
// Roles, each a small piece of simplify.cpp:
//   cost term      plane quadrics of the faces, uniform or area-weighted (+ boundary planes)
//   placement      place() in quadric.h (rank-revealing, never outside the neighbourhood)
//   legality       link condition, manifold/lock rules, normal-flip limit (see docs/simplify.md)
//   stop rule      target face count, or no legal collapse within max_error left
//   observer       progress reports; the library never prints
#pragma once

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "visimp/core/mesh.h"
#include "visimp/core/option_table.h"

namespace visimp {

enum class SimplifyMethod {
  qb,  ///< plain quadrics (Garland & Heckbert)
  vg,  ///< visibility-guided (Zhang & Turk): needs face_visibility
};

/// A replacement for the queue's cost (the cell-based cost of the walkthrough-LOD paper,
/// cells/lod_cost.h, for one). Placement, legality and the reported error stay the engine's
/// (the plain quadric's); only the order of the collapses changes. Vertex indices are the
/// input's (a collapse merges v1 into v0). Must be safe to call from a copy of the engine:
/// keep no state that collapses change — per-vertex state the engine should carry goes in
/// SimplifyOptions::vertex_weights.
class CollapseCost {
 public:
  struct Edge {
    VertexIndex v0, v1;
    Vec3 p0, p1, placed;   ///< mesh coordinates: the two ends and where the merged vertex goes
    Vec3 n0, n1;           ///< unit area-weighted vertex normals of the current mesh (zero: none)
    float w0 = 0, w1 = 0;  ///< the vertices' weights (SimplifyOptions::vertex_weights, merged by max)
  };
  virtual ~CollapseCost() = default;
  /// The collapse's cost, ≥ 0 (smaller first). +infinity refuses the collapse for now (a
  /// stop rule of the cost's own: the run ends with StopReason::error_limit when only refused
  /// collapses are left); the edge is asked again after a collapse next to it.
  virtual double cost(const Edge& edge) const = 0;
};

/// How much each input face's plane counts in the quadrics (docs/simplify.md, "Area-weighted
/// or uniform plane quadrics": area gives the lower image and RMS error on CAD parts, uniform
/// the lower Hausdorff distance on scans).
enum class QuadricWeights {
  area,     ///< a face's plane weighs its area (Garland's thesis, §5.3.3)
  uniform,  ///< every face's plane weighs 1 (Garland & Heckbert 1997; CGAL's GH policies)
};

struct SimplifyOptions {
  /// Stop once the mesh has at most this many faces (0: use target_ratio, or only max_error).
  std::size_t target_faces = 0;
  /// Fraction of the input's faces to keep, in (0, 1]; used when target_faces is 0 (0: unset).
  double target_ratio = 0;
  /// Never perform a collapse whose error exceeds this. The error is the RMS distance of the
  /// new vertex to the planes of the faces merged into it, relative to the input's
  /// bounding-box diagonal. Infinity: no limit. With no target, simplify until this stops it.
  double max_error = std::numeric_limits<double>::infinity();
  /// Weight of each face's plane in the quadrics.
  QuadricWeights quadric_weights = QuadricWeights::area;
  /// Area weights only: each face's plane weighs its area plus this many times the median
  /// face area (0: its area alone). Between area and uniform weights: the small faces of a
  /// thin detail are no longer nearly free to remove, which lowers the Hausdorff distance on
  /// scans, while a CAD part's large faces still outweigh the small faces of its fillets (their
  /// median is small), which keeps most of the area weights' lower image error. Must be a finite
  /// number >= 0. docs/simplify.md, "A floor at the median face area".
  double area_floor = 0;
  /// Weight of the planes through each boundary edge perpendicular to its face, as a multiple
  /// of one face's plane: W with uniform weights, W × the edge length squared with area
  /// weights (a face weighs its area). Keeps open outlines; 0 disables.
  double boundary_weight = 100.0;
  /// Never move or remove a boundary vertex.
  bool freeze_boundary = false;
  /// Reject a collapse that would turn any remaining face's normal by more than this angle,
  /// in degrees (0, 180]. 180 only rejects exactly flipped faces.
  double max_normal_change_deg = 80.0;
  /// Also reject a collapse after which a face around the new vertex and a face across one of
  /// its edges point more than ~154° apart (fold back onto each other) where they did not
  /// before. Off by default for now: it changes CAD results (thin plates keep their rims
  /// instead of becoming two sheets back to back); see docs/simplify.md, Known limits.
  bool prevent_folds = false;
  SimplifyMethod method = SimplifyMethod::qb;
  /// VG: V(t) in [0, 1] of every input face (visibility.h computes it). Unused by QB.
  std::vector<float> face_visibility;
  /// VG: each face's plane quadric is weighted by V(t)^p in the queue order. 2 is Zhang &
  /// Turk's eq. 5.10; smaller p discounts partly visible faces less (1: the weight is the
  /// share of views that see the face). Must be > 0.
  double visibility_exponent = 2.0;
  /// VG: a face that meets a more visible face at a crease (normals more than 30° apart) is
  /// weighted with that face's V: its plane is where the visible face ends, so moving off it
  /// moves a visible outline even when the face itself is seen only at grazing angles.
  /// Off by default (eq. 5.10 weighs each face by its own V); see docs/simplify.md.
  bool crease_visibility = false;
  /// Orders the queue instead of the quadric cost when set (not owned; must outlive the run).
  const CollapseCost* collapse_cost = nullptr;
  /// With collapse_cost: empty, or one weight per input vertex, handed to the cost; a merged
  /// vertex keeps the larger weight of the two.
  std::vector<float> vertex_weights;
  /// Worker threads (0: one per hardware thread). The result is the same for every count: the
  /// parallel phase's partitions do not depend on it (docs/simplify.md, "Two cores").
  unsigned threads = 0;
  /// One collapse sequence in queue order, without the parallel phase (set-up still uses the
  /// threads): what simplify_levels() runs for every level, so simplify() with this set equals
  /// the level at its target. Slower on big meshes at low targets; about the same or lower
  /// error (docs/simplify.md, "Many levels in one run").
  bool serial_collapses = false;
};

/// The command-line flags of SimplifyOptions, bound to `options` (help and defaults).
std::vector<OptionSpec> describe_options(SimplifyOptions& options);

/// Throws UsageError naming the flag when an option is out of range or no stop rule is given.
/// simplify() calls it; apps call it first so bad usage is reported before any I/O.
void check_options(const SimplifyOptions& options);

enum class StopReason {
  target_reached,     ///< face count <= target
  error_limit,        ///< every remaining collapse would exceed max_error
  no_legal_collapse,  ///< target not reached: every remaining edge is locked or illegal
  nothing_to_do,      ///< the input already had no more faces than the target
};
const char* to_string(StopReason reason);
/// "area" or "uniform": the --quadric-weights name, as JSON summaries write it.
const char* to_string(QuadricWeights weights);

/// Where SimplifyResult::seconds went (docs/simplify.md, "Where the time goes").
struct SimplifyStageSeconds {
  double setup = 0;           ///< the engine: spatial order, face lists, quadrics, the costed queue
  double parallel_phase = 0;  ///< 0 when the run does not use it
  double serial = 0;          ///< the collapse loop after it (for a level: every run up to that level)
  double extract = 0;         ///< the mesh out, in input order
};

struct SimplifyResult {
  std::size_t faces_in = 0, faces_out = 0;
  std::size_t vertices_in = 0, vertices_out = 0;
  std::size_t target_faces = 0;  ///< the target in effect (0 when only max_error stops)
  std::size_t collapses = 0;
  std::size_t parallel_collapses = 0;  ///< of `collapses`, those of the parallel phase (docs/simplify.md, "Two cores")
  std::size_t rejected_collapses = 0;  ///< candidates refused by a legality filter (counted per attempt)
  /// Edges costed again after the set-up: at a collapse, or when a dated entry reached the
  /// front of the (lazy) queue. Its placements are most of a run's arithmetic.
  std::size_t requeued_edges = 0;
  std::size_t locked_vertices = 0;     ///< vertices never moved: non-manifold, misoriented, frozen boundary
  std::size_t dropped_faces = 0;       ///< input faces with a repeated vertex index, removed first (no area, no fan)
  /// Largest error of a performed collapse, same unit as max_error (relative to the diagonal).
  double max_error = 0;
  StopReason stop_reason = StopReason::nothing_to_do;
  double seconds = 0;
  SimplifyStageSeconds stage_seconds;
};

/// Progress and tracing; the default does nothing.
class SimplifyObserver {
 public:
  virtual ~SimplifyObserver() = default;
  /// Fraction of the planned collapses done, in [0, 1]; called about a hundred times per run.
  virtual void on_progress(double /*fraction*/) {}
};

struct Simplified {
  Mesh mesh;
  SimplifyResult result;
};

/// Simplifies a copy of `input` (never modified). Faces and vertices that survive keep their
/// input order and quality values. Throws UsageError for out-of-range options and
/// InvalidMeshError for an invalid mesh (see validate.h).
Simplified simplify(const Mesh& input, const SimplifyOptions& options, SimplifyObserver* observer = nullptr);
/// The same result, for a caller done with `input`: its faces are released once the engine
/// has its own copy (12 bytes per face less at the peak: 168 MB at 14M faces), and a mesh
/// already at its target is moved, not copied. `input` is left valid but unspecified.
Simplified simplify(Mesh&& input, const SimplifyOptions& options, SimplifyObserver* observer = nullptr);

/// Many levels in one collapse sequence: the mesh at each face count in `targets` (any order;
/// results in the same order). The sequence runs without the parallel phase: each level
/// equals simplify() with that target_faces and serial_collapses = true, bit for bit (a level
/// ending one face below its target is finished on a copy of the engine, so the run goes on as
/// a single run to the next target would). options.target_* and serial_collapses are ignored;
/// each result's seconds are from the start of the run to that level.
std::vector<Simplified> simplify_levels(const Mesh& input, const SimplifyOptions& options,
                                        const std::vector<std::size_t>& targets, SimplifyObserver* observer = nullptr);

}  // namespace visimp
