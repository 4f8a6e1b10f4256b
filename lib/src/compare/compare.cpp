#include "visimp/compare/compare.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <iomanip>
#include <sstream>

#include "visimp/core/bounding_box.h"
#include "visimp/core/errors.h"
#include "visimp/core/mesh_stats.h"
#include "visimp/core/portable_random.h"
#include "visimp/core/stopwatch.h"
#include "visimp/core/validate.h"

namespace visimp {
namespace {

// Zhang & Turk's Table 2 measure for one level: how much less image RMS error `other` has
// than QB, in percent of QB's (0 when QB's is 0: nothing to improve on).
double percent_less_than_qb(double qb_rms, double other_rms) {
  return qb_rms > 0 ? 100.0 * (qb_rms - other_rms) / qb_rms : 0.0;
}

// Forwards one stage's progress to the compare observer.
class StageProgress final : public RenderObserver, public SimplifyObserver {
 public:
  StageProgress(CompareObserver* observer, std::string stage) : observer_(observer), stage_(std::move(stage)) {}
  void on_render_progress(double fraction) override { on_progress(fraction); }
  void on_progress(double fraction) override {
    if (observer_) observer_->on_compare_progress(stage_, fraction);
  }

 private:
  CompareObserver* observer_;
  std::string stage_;
};

std::vector<CompareLevel> run_method(const Mesh& input_with_v, const SimplifyOptions& options,
                                     const std::vector<std::size_t>& targets, StageProgress& progress,
                                     double& seconds) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<Simplified> levels = simplify_levels(input_with_v, options, targets, &progress);
  seconds = seconds_since(start);
  std::vector<CompareLevel> out(levels.size());
  for (std::size_t i = 0; i < levels.size(); ++i) {
    out[i].target = targets[i];
    out[i].faces = levels[i].mesh.num_faces();
    out[i].seconds_simplify = levels[i].result.seconds;
    out[i].stop_reason = levels[i].result.stop_reason;
    out[i].mesh = std::move(levels[i].mesh);
  }
  return out;
}

}  // namespace

void check_options(const CompareOptions& o) {
  if (o.targets.empty() && (o.levels < 1 || o.levels > 64))
    throw OptionError(&o.levels, "CompareOptions::levels", "must be in 1..64");
  if (!(o.min_ratio > 0 && o.min_ratio <= o.max_ratio && o.max_ratio < 1)) {
    throw OptionError(nullptr, "CompareOptions", "needs 0 < min_ratio <= max_ratio < 1");
  }
  for (std::size_t t : o.targets)
    if (t < 4) throw OptionError(&o.targets, "CompareOptions::targets", "must all be >= 4 faces");
  if (o.tie_noise_runs > 100)
    throw OptionError(&o.tie_noise_runs, "CompareOptions::tie_noise_runs", "must be in 0..100 runs");
  check_options(o.visibility);
}

std::vector<OptionSpec> describe_options(CompareOptions& o, std::vector<OptionSpec> sampling) {
  std::vector<OptionSpec> specs = {
      option_spec("--levels", "K", o.levels, "number of levels, log-spaced over --min-ratio..--max-ratio"),
      option_spec("--min-ratio", "R", o.min_ratio, "smallest level as a fraction of IN's faces"),
      option_spec("--max-ratio", "R", o.max_ratio, "largest level as a fraction of IN's faces"),
      switch_spec("--weights-from-quality", o.visibility_from_quality,
                  "take V from IN's face quality (a 'visimp visibility' output) instead of rendering"),
      option_spec("--metro-samples", "N", o.metro_samples,
                  "Metro face samples per direction (0: 10 x IN's faces, at most 2,000,000)"),
      option_spec("--image-resolution", "R", o.image.resolution, "image-error view size in pixels, 16..8192"),
      option_spec("--image-supersample", "S", o.image.supersample,
                  "image-error samples per pixel side, averaged, 1..8 (1: point sampling)"),
      option_spec("--tie-noise", "N", o.tie_noise_runs,
                  "also run N near-tie runs (VG with V in [0.99, 1]) and say per level whether VG's lead "
                  "exceeds their spread, 0..100")};
  for (OptionSpec& spec : sampling) specs.push_back(std::move(spec));
  for (OptionSpec& spec : describe_options(o.visibility)) specs.push_back(std::move(spec));
  // The levels set the face counts and always run one serial sequence: --target, --ratio and
  // --serial-collapses would be silently ignored.
  for (OptionSpec& spec : describe_options(o.simplify))
    if (spec.flag != "--target" && spec.flag != "--ratio" && spec.flag != "--serial-collapses")
      specs.push_back(std::move(spec));
  return specs;
}

std::vector<std::size_t> default_targets(std::size_t faces, std::size_t levels, double min_ratio, double max_ratio) {
  std::vector<std::size_t> targets;
  for (std::size_t i = 0; i < levels; ++i) {
    const double t = levels == 1 ? 0.0 : double(i) / double(levels - 1);
    const double ratio = max_ratio * std::pow(min_ratio / max_ratio, t);
    std::size_t n = static_cast<std::size_t>(std::llround(ratio * double(faces) / 2.0)) * 2;
    n = std::max<std::size_t>(n, 4);
    if (targets.empty() || n < targets.back()) targets.push_back(n);
  }
  return targets;
}

CompareResult compare_methods(const Mesh& input, const CameraSet& cameras, Renderer& renderer,
                              const CompareOptions& options, CompareObserver* observer) {
  check_options(options);
  require_valid(input, "compare input");
  CompareResult r;
  r.faces_in = input.num_faces();
  r.diagonal = bounding_box(input).diagonal();
  r.targets = options.targets.empty()
                  ? default_targets(input.num_faces(), options.levels, options.min_ratio, options.max_ratio)
                  : options.targets;
  std::sort(r.targets.begin(), r.targets.end(), std::greater<>());
  r.targets.erase(std::unique(r.targets.begin(), r.targets.end()), r.targets.end());
  if (r.targets.front() >= input.num_faces()) {
    throw UsageError("target " + std::to_string(r.targets.front()) + " is not below the input's " +
                     std::to_string(input.num_faces()) + " faces");
  }

  auto t = std::chrono::steady_clock::now();
  r.visibility_from_quality = options.visibility_from_quality;
  r.visibility_exponent = options.simplify.visibility_exponent;
  r.crease_visibility = options.simplify.crease_visibility;
  r.quadric_weights = options.simplify.quadric_weights;
  r.area_floor = options.simplify.area_floor;
  if (options.visibility_from_quality) {
    r.visibility = visibility_from_face_quality(input);
  } else {
    StageProgress progress(observer, "visibility");
    r.visibility = compute_visibility(input, cameras, renderer, options.visibility, &progress);
  }
  r.seconds_visibility = seconds_since(t);

  // Both methods simplify the input carrying V as face quality, so every result says how
  // visible its surviving faces were.
  Mesh input_with_v = input;
  input_with_v.face_quality = r.visibility.face;
  SimplifyOptions qb = options.simplify, vg = options.simplify;
  qb.method = SimplifyMethod::qb;
  qb.face_visibility.clear();
  vg.method = SimplifyMethod::vg;
  vg.face_visibility = r.visibility.face;
  {
    StageProgress progress(observer, "qb");
    r.qb = run_method(input_with_v, qb, r.targets, progress, r.seconds_qb);
  }
  {
    StageProgress progress(observer, "vg");
    r.vg = run_method(input_with_v, vg, r.targets, progress, r.seconds_vg);
  }

  SurfaceDistanceOptions metro;
  metro.samples =
      options.metro_samples ? options.metro_samples : std::min<std::size_t>(10 * input.num_faces(), 2'000'000);
  metro.face_visibility = r.visibility.face;
  metro.threads = static_cast<int>(options.image.threads);  // the caller's --threads, as the image error
  const std::size_t total = r.qb.size() + r.vg.size();
  std::size_t done = 0;
  // The input's index and samples once for all 2 x levels (at 14M faces: 20 s each time).
  const SurfaceDistanceReference reference(input_with_v);
  // And the input's 20 views once for every level and tie-noise run.
  const ImageErrorReference image_reference(input, options.image);
  for (std::vector<CompareLevel>* method : {&r.qb, &r.vg}) {
    for (CompareLevel& level : *method) {
      t = std::chrono::steady_clock::now();
      level.distance = reference.distance_to(level.mesh, metro);
      level.seconds_metro = seconds_since(t);
      t = std::chrono::steady_clock::now();
      level.image = image_reference.error_to(level.mesh);
      level.seconds_image = seconds_since(t);
      if (observer) observer->on_compare_progress("errors", double(++done) / double(total));
    }
  }
  if (options.tie_noise_runs > 0) {
    t = std::chrono::steady_clock::now();
    r.tie_noise_percent.assign(r.targets.size(), {});
    for (std::size_t run = 1; run <= options.tie_noise_runs; ++run) {
      SimplifyOptions near_tie = vg;
      SplitMix64 random(run);
      for (float& v : near_tie.face_visibility) v = static_cast<float>(1.0 - 0.01 * random.uniform());
      StageProgress progress(observer, "tie noise " + std::to_string(run));
      double seconds = 0;
      const std::vector<CompareLevel> levels = run_method(input, near_tie, r.targets, progress, seconds);
      for (std::size_t i = 0; i < levels.size(); ++i) {
        const double run_rms = image_reference.error_to(levels[i].mesh).rms;
        r.tie_noise_percent[i].push_back(percent_less_than_qb(r.qb[i].image.rms, run_rms));
      }
    }
    r.seconds_tie_noise = seconds_since(t);
  }

  double sum = 0;
  std::size_t counted = 0;
  r.less_image_error_percent_per_level.assign(r.targets.size(), 0.0);
  for (std::size_t i = 0; i < r.targets.size(); ++i) {
    if (!(r.qb[i].image.rms > 0)) continue;
    r.less_image_error_percent_per_level[i] = percent_less_than_qb(r.qb[i].image.rms, r.vg[i].image.rms);
    sum += r.less_image_error_percent_per_level[i];
    ++counted;
  }
  r.less_image_error_percent = counted ? sum / double(counted) : 0.0;
  return r;
}

std::string unreached_levels_note(const CompareResult& r) {
  std::ostringstream s;
  for (const auto& [name, levels] : {std::pair{"QB", &r.qb}, std::pair{"VG", &r.vg}}) {
    std::size_t unreached = 0;
    const CompareLevel* lowest = nullptr;
    for (const CompareLevel& l : *levels) {
      if (l.faces <= l.target) continue;
      ++unreached;
      if (lowest == nullptr || l.faces < lowest->faces) lowest = &l;
    }
    if (unreached == 0) continue;
    s << (s.tellp() > 0 ? "; " : "") << name << " stops at " << lowest->faces << " faces, above " << unreached
      << " of the " << levels->size() << " targets (" << to_string(lowest->stop_reason) << ")";
  }
  if (s.tellp() > 0) s << ": those levels repeat the mesh each method stopped at";
  return s.str();
}

const char* to_string(TieNoiseVerdict verdict) {
  switch (verdict) {
    case TieNoiseVerdict::not_measured:
      return "not_measured";
    case TieNoiseVerdict::above:
      return "above";
    case TieNoiseVerdict::inside:
      return "inside";
    case TieNoiseVerdict::below:
      return "below";
  }
  return "?";
}

TieNoiseVerdict tie_noise_verdict(const CompareResult& r, std::size_t level) {
  if (level >= r.tie_noise_percent.size() || r.tie_noise_percent[level].empty()) return TieNoiseVerdict::not_measured;
  const std::vector<double>& runs = r.tie_noise_percent[level];
  const double lead = r.less_image_error_percent_per_level[level];
  // The runs and QB itself (0%) span the spread of near-tie orders.
  const double low = std::min(0.0, *std::min_element(runs.begin(), runs.end()));
  const double high = std::max(0.0, *std::max_element(runs.begin(), runs.end()));
  return lead > high ? TieNoiseVerdict::above : (lead < low ? TieNoiseVerdict::below : TieNoiseVerdict::inside);
}

TieNoiseCounts count_tie_noise_verdicts(const CompareResult& r) {
  TieNoiseCounts counts;
  for (std::size_t i = 0; i < r.targets.size(); ++i) {
    switch (tie_noise_verdict(r, i)) {
      case TieNoiseVerdict::above:
        ++counts.above;
        break;
      case TieNoiseVerdict::inside:
        ++counts.inside;
        break;
      case TieNoiseVerdict::below:
        ++counts.below;
        break;
      case TieNoiseVerdict::not_measured:
        break;
    }
  }
  return counts;
}

std::string table2_row(const CompareResult& r, const std::string& name) {
  std::ostringstream s;
  s << std::fixed;
  s << "| model | faces | V(M) | visibility s | VG simplification s | QB simplification s | less image error with VG "
       "|\n"
    << "|---|---|---|---|---|---|---|\n"
    << "| " << name << " | " << r.faces_in << " | " << std::setprecision(3) << r.visibility.mesh << " | "
    << std::setprecision(2) << r.seconds_visibility << " | " << r.seconds_vg << " | " << r.seconds_qb << " | "
    << r.less_image_error_percent << "% |\n";
  return s.str();
}

}  // namespace visimp
