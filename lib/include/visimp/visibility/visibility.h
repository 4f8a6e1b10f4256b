// The visibility measure (Zhang & Turk 2002, §3–4): how visible each triangle is from a
// sphere of orthographic cameras, weighted by viewing angle.
//
//   V(t) = Σ_v F(t,v) · max(0, R(v)·N(t)) / Σ_v max(0, R(v)·N(t))           (eq. 4.3)
//   V(M) = Σ_t area(t) V(t) / Σ_t area(t)                                      (eq. 3.2)
//
// F(t, v) = 1 when camera v sees any part of t: t owns a pixel of v's ID buffer, or (the
// paper's fix for faces smaller than a pixel) one of t's vertices lies within a tolerance of
// the surface shown around it (the bilinear interpolation of the four depths at the vertex,
// so a part just behind a thin shell stays hidden), on a silhouette, or at a corner of a
// face shown next to it (docs/visibility.md "The depth test"). With `fractional`, F is the
// fraction of t's projected area that owns pixels (the paper's suggested improvement).
//
// Winding: N(t) is not taken from the input. Faces are wound canonically first
// (core/orientation.h): closed surfaces outward, where eq. 4.3 applies as written; a face of
// an open or non-manifold surface is measured from both sides, each with its own weights,
// and V(t) is the better-seen side. Reversing any faces of the input changes nothing.
// `trust_winding` keeps the paper's one-sided measure on the input's normals.
//
// Pipeline: refine long edges → render every camera (any Renderer) → tally → V per refined
// face → V per input face (area-weighted over its sub-faces) and per vertex (area-weighted
// over incident faces) → V(M).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "visimp/cameras/camera_set.h"
#include "visimp/core/mesh.h"
#include "visimp/core/option_table.h"
#include "visimp/render/image.h"
#include "visimp/render/renderer.h"
#include "visimp/visibility/refine.h"
#include "visimp/visibility/tally.h"

namespace visimp {

struct VisibilityOptions {
  /// Cosine of the worst viewing angle the refinement targets (0.25 ≈ 75.5°, the paper's
  /// choice): l = pixel / worst_view_cosine. Range (0, 1].
  double worst_view_cosine = 0.25;
  /// Split edges longer than l (the paper's first fix). Off only to study its effect.
  bool refine = true;
  /// The depth-tolerance test for faces that own no pixel (the paper's second fix).
  bool depth_test = true;
  /// How far (pixels) a vertex may lie behind the surface shown around it (the bilinear
  /// interpolation of the four depths) and still count as seen (docs/visibility.md). Range [0, 16].
  double depth_tolerance_pixels = 0.25;
  /// Take the input's face normals as outward: one-sided F, no reorientation (the paper's
  /// measure as written; wrong for inward-wound or mixed input).
  bool trust_winding = false;
  /// F = visible fraction of the projected area instead of 0/1.
  bool fractional = false;
  /// Refinement budget; more faces than this is an error, not a slow run.
  std::size_t max_refined_faces = 30'000'000;
  /// Threads that prepare the mesh and finish V (0 = one per hardware thread; the renderer
  /// has its own). V does not depend on it.
  unsigned threads = 0;
};

std::vector<OptionSpec> describe_options(VisibilityOptions& options);
/// Throws UsageError for out-of-range values.
void check_options(const VisibilityOptions& options);

struct VisibilityStats {
  std::size_t input_faces = 0;
  std::size_t refined_faces = 0;  ///< faces rendered (= input_faces when no refinement)
  int refinement_rounds = 0;
  double max_edge_length = 0;  ///< l, input units
  std::size_t cameras = 0;
  int resolution = 0;
  bool back_faces_culled = false;    ///< every face lies on a closed outward surface: all culled
  std::size_t one_sided_faces = 0;   ///< input faces on closed surfaces: front side only, culled
  std::size_t two_sided_faces = 0;   ///< input faces of open or non-manifold surfaces: both sides
  std::size_t seen_from_behind = 0;  ///< input faces whose better-seen side is their back
  std::size_t degenerate_faces = 0;  ///< zero area: V is the mean of their vertices' V
  std::size_t unfaced_faces = 0;     ///< no camera in front of them: V likewise from vertices
  std::size_t hidden_faces = 0;      ///< V = 0: no camera saw any part of them
  double hidden_area_fraction = 0;   ///< their share of the surface area
  /// prepare = orient + refine + scene: winding patches, splitting long edges (or only
  /// checking that none is long), and the render scene in spatial order.
  double seconds_prepare = 0, seconds_orient = 0, seconds_refine = 0, seconds_scene = 0;
  double seconds_render = 0, seconds_aggregate = 0, seconds_total = 0;
};

struct Visibility {
  std::vector<float> face;  ///< V(t) per input face, in [0, 1]: the better-seen side
  /// Per input face, V of each side: front = where the input's normal points. One of them
  /// is 0 for a face of a closed surface (its inside is never seen).
  std::vector<float> face_front, face_back;
  std::vector<float> vertex;  ///< per vertex, area-weighted over incident faces
  double mesh = 0;            ///< V(M)
  VisibilityStats stats;
};

/// Holds a mesh prepared for visibility (refined, in render form) so camera slices can be
/// rendered separately and tallies merged before finish().
class VisibilityJob {
 public:
  /// `resolution` fixes l; the renderer passed to render() must use the same resolution.
  /// The job keeps a reference to `mesh`, which must outlive it (a temporary is refused).
  VisibilityJob(const Mesh& mesh, int resolution, const VisibilityOptions& options);
  VisibilityJob(const Mesh&& mesh, int resolution, const VisibilityOptions& options) = delete;

  /// Tallies cameras [first, last) of `cameras`. `also`, when given, receives the same
  /// frames (of scene(); see scene_input_faces()).
  VisibilityTally render(const CameraSet& cameras, std::size_t first, std::size_t last, Renderer& renderer,
                         RenderObserver* observer = nullptr, FrameConsumer* also = nullptr) const;

  /// V from a complete tally (throws UsageError if cameras are missing or the key differs).
  Visibility finish(const VisibilityTally& tally) const;

  /// What a tally of this job over `cameras` must carry.
  TallyKey key(const CameraSet& cameras) const;
  const VisibilityStats& stats() const { return stats_; }
  std::uint64_t mesh_hash() const { return mesh_hash_; }
  /// The refined faces in render order: feed it to other FrameConsumers for one sampling.
  const RenderScene& scene() const { return scene_; }
  /// For each face of scene(): the input face it is (part of).
  std::vector<std::uint32_t> scene_input_faces() const;

 private:
  const Mesh& input_;
  VisibilityOptions options_;
  std::vector<std::uint8_t> input_reversed_;   ///< per input face: canonical winding is the reverse
  std::vector<std::uint8_t> input_one_sided_;  ///< per input face: on a closed outward surface
  std::vector<std::uint8_t> input_degenerate_;  ///< per input face: is_degenerate (core/mesh_stats.h)
  int resolution_;
  std::optional<RefinedMesh> refined_;
  RenderScene scene_;
  std::vector<std::uint32_t> scene_order_;  ///< scene face → face of rendered_mesh()
  std::size_t one_sided_scene_faces_ =
      0;  ///< the scene's first faces: front side only (and culled, unless trust_winding)
  std::vector<std::array<float, 3>> unit_normals_;  ///< per refined face, zero if degenerate
  std::uint64_t mesh_hash_ = 0;
  VisibilityStats stats_;

  const Mesh& rendered_mesh() const { return refined_ ? refined_->mesh : input_; }
};

/// The options a tally was computed with (to finish a merged tally).
VisibilityOptions options_of(const TallyKey& key);

/// One call: refine, render all cameras, finish.
Visibility compute_visibility(const Mesh& mesh, const CameraSet& cameras, Renderer& renderer,
                              const VisibilityOptions& options = {}, RenderObserver* observer = nullptr);

/// V read back from a mesh's face quality (a `visimp visibility` output): face V and V(M);
/// no vertex V, no stats. Throws InvalidMeshError when the quality is missing or outside [0, 1].
Visibility visibility_from_face_quality(const Mesh& mesh);

/// The paper's colour scale (Fig. 2): 0–1/3 white→red, 1/3–2/3 red→yellow, 2/3–1 yellow→green.
Rgb visibility_color(double v);

/// A size×size picture of `mesh` from a 3/4 view above the front right, each face coloured
/// by visibility_color(face_visibility[f]) and flat-shaded.
RgbImage render_visibility_map(const Mesh& mesh, const std::vector<float>& face_visibility, int size);

/// The result of leaving out never-seen geometry (`--drop-hidden`).
struct HiddenRemoval {
  Mesh mesh;  ///< faces with V > threshold and the vertices they or no face use, both in input order
  std::vector<float> face_visibility;  ///< V of the kept faces
  std::size_t faces_removed = 0;
  double area_removed = 0;           ///< input units²
  double area_fraction_removed = 0;  ///< of the input's total area
};

/// Removes every face with V ≤ threshold (threshold in [0, 1); 0 removes exactly the faces
/// no camera saw). Face and vertex quality, when present, follow their faces and vertices.
HiddenRemoval drop_hidden_faces(const Mesh& mesh, const std::vector<float>& face_visibility, double threshold);

/// Closed, consistently oriented, every component enclosing positive volume: then every
/// back face is hidden behind a front face and need not be drawn.
bool back_faces_always_hidden(const Mesh& mesh);

}  // namespace visimp
