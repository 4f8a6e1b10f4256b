// visimp compare: the QB-vs-VG report (docs/compare.md).
#include <algorithm>
#include <filesystem>
#include <iostream>

#include "backends.h"
#include "cli.h"
#include "commands.h"
#include "visimp/compare/compare.h"
#include "visimp/core/errors.h"
#include "visimp/report/json.h"
#include "visimp/report/option_values.h"

namespace visimp::app {
namespace {

class CompareProgress final : public CompareObserver {
 public:
  void on_compare_progress(const std::string& stage, double fraction) override {
    if (stage != stage_) {
      bar_.emplace(stage);
      stage_ = stage;
    }
    bar_->on_progress(fraction);
  }

 private:
  std::string stage_;
  std::optional<ProgressBar> bar_;
};

}  // namespace

int run_compare(const Args& args) {
  CompareOptions options;
  SamplingOptions sampling;
  StreamOptions stream;
  std::string directory, targets_text;
  ArgParser parser("visimp compare IN [-o DIR] [--targets N,N,.. | --levels K] [options]",
                   "Simplifies IN with QB and with VG to the same face counts (one collapse run each), measures\n"
                   "every result against IN (Metro-style geometric error, visibility-weighted error, image RMS error\n"
                   "of 20 flat-shaded views) and writes results.csv, results.json, SVG plots, the meshes, PNGs and\n"
                   "report.html to DIR (default: <IN's name>_compare). Prints Zhang & Turk's Table 2 row.",
                   1);
  parser.add(option_spec("-o", "DIR", directory, "output directory (created if missing)"));
  // The options a comparison depends on: parsed from them, and listed in the JSON summary.
  auto comparison_specs = [&] {
    std::vector<OptionSpec> specs = {option_spec("--targets", "N,N,..", targets_text, "face counts to compare at")};
    for (OptionSpec& spec : describe_options(options, describe_options(sampling))) specs.push_back(std::move(spec));
    return specs;
  };
  parser.add(comparison_specs());
  parser.add(option_spec("--format", "F", stream.format, "format of IN when it is '-': ply, obj, off or stl"));
  parser.add(switch_spec("--json", stream.json, "print a machine-readable JSON summary"));
  if (!parser.parse(args)) return 0;
  if (!targets_text.empty()) options.targets = parse_count_list(targets_text, "--targets");
  check_pixels(static_cast<std::size_t>(options.image.resolution), "--image-resolution");  // negative: huge
  if (options.image.supersample < 1 || options.image.supersample > 8)
    throw UsageError("--image-supersample must be in 1..8");
  options.image.threads = static_cast<unsigned>(std::min<std::size_t>(sampling.threads, kMaxThreads));
  options.simplify.threads = options.image.threads;
  options.visibility.threads = options.image.threads;
  options.simplify.target_ratio = 0.5;  // placeholder so check_options accepts it; levels set the targets
  if (!(options.min_ratio > 0 && options.min_ratio <= options.max_ratio && options.max_ratio < 1))
    throw UsageError("--min-ratio and --max-ratio must satisfy 0 < min <= max < 1");
  check_options(options);
  check_options(options.simplify);
  const std::string& in = parser.positionals()[0];
  if (directory.empty()) {
    directory = in == "-" ? std::string("stdin_compare") : std::filesystem::path(in).stem().string() + "_compare";
  }
  const CameraSet cameras = camera_set_from_spec(sampling.cameras);
  const auto renderer = make_renderer(sampling.backend, render_options(sampling));

  const Mesh mesh = read_input(in, stream);
  require_faces(mesh, in, "compare");
  CompareResult result;
  {
    CompareProgress progress;
    try {
      result = compare_methods(mesh, cameras, *renderer, options, &progress);
    } catch (const InvalidMeshError& e) {  // name the file: the library does not know it
      throw InvalidMeshError(in + ": " + e.what());
    }
  }
  const std::vector<std::string> written = write_compare_report(result, mesh, in, directory, comparison_specs());
  const std::string name = in == "-" ? "stdin" : std::filesystem::path(in).stem().string();
  const std::string unreached = unreached_levels_note(result);
  if (!unreached.empty()) std::cerr << "visimp compare: note: " << unreached << "\n";
  if (stream.json) {
    JsonWriter json(std::cout);
    json.begin_object()
        .field("command", "compare")
        .field("input", in)
        .field("input_format", input_format_name(stream))
        .field("format_detected", input_format_detected(stream))
        .field("directory", directory)
        .field("faces_in", result.faces_in)
        .field("mesh_visibility", result.visibility.mesh)
        .field("less_image_error_with_vg_percent", result.less_image_error_percent)
        .field("unreached_levels", unreached)  // empty when both methods reached every level
        .key("options");
    write_option_values(json, comparison_specs());
    if (!result.tie_noise_percent.empty()) {
      const TieNoiseCounts v = count_tie_noise_verdicts(result);
      json.key("levels_vs_tie_noise")
          .begin_object()
          .field("above", v.above)
          .field("inside", v.inside)
          .field("below", v.below)
          .end_object();
    }
    json.key("seconds")
        .begin_object()
        .field("visibility", result.seconds_visibility)
        .field("qb", result.seconds_qb)
        .field("vg", result.seconds_vg)
        .field("tie_noise", result.seconds_tie_noise)
        .end_object();
    json.key("files").begin_array();
    for (const std::string& f : written) json.value(f);
    json.end_array();
    json.end_object();
  } else {
    std::cout << table2_row(result, name);
    if (!result.tie_noise_percent.empty()) {
      const TieNoiseCounts v = count_tie_noise_verdicts(result);
      std::cout << "VG's lead against " << options.tie_noise_runs
                << " near-tie run(s), per level: above their spread at " << v.above << ", inside at " << v.inside
                << ", below at " << v.below << " of " << result.targets.size() << "\n";
    }
    std::cout << "report: " << (std::filesystem::path(directory) / "report.html").string() << "\n";
  }
  return 0;
}

}  // namespace visimp::app
