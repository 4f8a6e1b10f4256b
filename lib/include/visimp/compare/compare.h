// QB against VG (Zhang & Turk 2002 §5, Fig. 4 and Table 2): visibility once, both methods to
// the same levels in one collapse run each, and for every result the Metro-style error, the
// visibility-weighted error and the image error, each stage timed. write_compare_report()
// turns a CompareResult into the files `visimp compare` promises (docs/compare.md).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "visimp/cameras/camera_set.h"
#include "visimp/core/mesh.h"
#include "visimp/core/option_table.h"
#include "visimp/metrics/image_error.h"
#include "visimp/metrics/surface_distance.h"
#include "visimp/render/renderer.h"
#include "visimp/simplify/simplify.h"
#include "visimp/visibility/visibility.h"

namespace visimp {

struct CompareOptions {
  /// Face counts to compare at; empty: `levels` counts log-spaced over [min_ratio, max_ratio]
  /// of the input's faces (default_targets).
  std::vector<std::size_t> targets;
  std::size_t levels = 7;
  double min_ratio = 0.02, max_ratio = 0.30;
  /// Shared by both methods (method and face_visibility are set per method).
  SimplifyOptions simplify;
  VisibilityOptions visibility;
  /// V from the input's face quality instead of rendering it.
  bool visibility_from_quality = false;
  /// Metro face samples per direction; 0: 10 × the input's faces, at most 2,000,000.
  std::size_t metro_samples = 0;
  ImageErrorOptions image;
  /// Runs of "QB up to near-ties": VG with V drawn uniformly from [0.99, 1] (seed = run), whose
  /// queue differs from QB's only where costs are within 2%. Their image error against QB's
  /// at each level measures how far the order of near-equal collapses alone moves a level;
  /// a QB–VG difference inside that spread is not a lead. 0: not measured.
  std::size_t tie_noise_runs = 0;
};

/// Throws UsageError for out-of-range values.
void check_options(const CompareOptions& options);

/// The comparison's settings as `visimp compare`'s flags: its own (--levels .. --tie-noise,
/// the image-error view size and supersampling), then `sampling` (the caller's specs of its
/// cameras and renderer), then VisibilityOptions' and SimplifyOptions' without --target,
/// --ratio and --serial-collapses (the levels set them). Not --targets (a list): callers add
/// it. The one list behind the app's flags and results.json's `options` from every caller
/// (write_compare_report), in the same order.
std::vector<OptionSpec> describe_options(CompareOptions& options, std::vector<OptionSpec> sampling = {});

/// `levels` face counts from max_ratio·faces down to min_ratio·faces, evenly spaced in log,
/// rounded to even numbers (closed meshes lose faces two at a time), distinct, ≥ 4.
std::vector<std::size_t> default_targets(std::size_t faces, std::size_t levels, double min_ratio, double max_ratio);

/// One method at one level.
struct CompareLevel {
  std::size_t target = 0, faces = 0;
  double seconds_simplify = 0;  ///< from the start of the method's run to this level
  SurfaceDistance distance;     ///< input (A, with V) against the result (B)
  ImageError image;
  double seconds_metro = 0, seconds_image = 0;
  /// Why the run ended at this level: target_reached, or no_legal_collapse when the method
  /// cannot get down to the target (locked non-manifold parts, components at their minimum):
  /// then `faces` > `target` and later levels repeat the same mesh.
  StopReason stop_reason = StopReason::target_reached;
  Mesh mesh;
};

struct CompareResult {
  std::size_t faces_in = 0;
  double diagonal = 0;    ///< input bounding-box diagonal: relative errors divide by it
  Visibility visibility;  ///< V of the input (stats empty when read from quality)
  bool visibility_from_quality = false;
  double visibility_exponent = 2;  ///< VG's weighting, as run (SimplifyOptions)
  bool crease_visibility = false;
  /// Both methods' plane weights, as run (SimplifyOptions::quadric_weights and area_floor):
  /// two runs' files say whether they weighed the faces alike.
  QuadricWeights quadric_weights = QuadricWeights::area;
  double area_floor = 0;
  double seconds_visibility = 0;
  std::vector<std::size_t> targets;       ///< descending
  std::vector<CompareLevel> qb, vg;       ///< one per target, same order
  double seconds_qb = 0, seconds_vg = 0;  ///< each method's whole collapse run
  /// Per target: 100·(QB − VG)/QB of the image RMS; their mean is Table 2's last column.
  std::vector<double> less_image_error_percent_per_level;
  double less_image_error_percent = 0;
  /// Per target, with tie_noise_runs > 0: 100·(QB − run)/QB of the image RMS of each near-tie
  /// run (CompareOptions::tie_noise_runs); empty otherwise.
  std::vector<std::vector<double>> tie_noise_percent;
  double seconds_tie_noise = 0;
};

/// Progress of the stages, for a progress bar.
class CompareObserver {
 public:
  virtual ~CompareObserver() = default;
  /// `stage`: "visibility", "qb", "vg", "errors"; fraction of that stage done.
  virtual void on_compare_progress(const std::string& /*stage*/, double /*fraction*/) {}
};

/// Throws UsageError / InvalidMeshError like the stages it runs.
CompareResult compare_methods(const Mesh& input, const CameraSet& cameras, Renderer& renderer,
                              const CompareOptions& options, CompareObserver* observer = nullptr);

/// Writes into `directory` (created if missing; each file atomically): results.csv,
/// results.json, four SVG plots, qb_<faces>.ply and vg_<faces>.ply per level, visibility.png,
/// side_by_side.png (original | QB | VG at the middle level) and report.html. Returns the paths
/// written. `input_name` is what the report calls the input. `options`, when given (the specs
/// of the options structs as run, e.g. the command line's), go to results.json as `options`
/// (write_option_values), so that the report says everything it was made with.
std::vector<std::string> write_compare_report(const CompareResult& result, const Mesh& input,
                                              const std::string& input_name, const std::string& directory,
                                              const std::vector<OptionSpec>& options = {});

/// Where VG's lead at a level (less_image_error_percent_per_level) lies against the range
/// spanned by that level's near-tie runs and QB itself (0%).
enum class TieNoiseVerdict { not_measured, above, inside, below };
const char* to_string(TieNoiseVerdict verdict);
TieNoiseVerdict tie_noise_verdict(const CompareResult& result, std::size_t level);

/// How many levels got each verdict (all 0 without near-tie runs).
struct TieNoiseCounts {
  std::size_t above = 0, inside = 0, below = 0;
};
TieNoiseCounts count_tie_noise_verdicts(const CompareResult& result);

/// One sentence naming, per method, the levels it could not reach and the face count it
/// stopped at ("QB stops at 7088 faces, above 6 of the 7 targets (no_legal_collapse); ...");
/// empty when both methods reached every target.
std::string unreached_levels_note(const CompareResult& result);

/// Zhang & Turk's Table 2 row as text: faces, V(M), seconds of visibility and of VG
/// simplification, % less image error with VG than QB.
std::string table2_row(const CompareResult& result, const std::string& name);

}  // namespace visimp
