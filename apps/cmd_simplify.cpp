// visimp simplify: QB or VG edge collapse to one target or many levels in one run, optionally
// leaving out never-seen faces first (docs/simplify.md).
#include <chrono>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "backends.h"
#include "cli.h"
#include "commands.h"
#include "visimp/compare/compare.h"
#include "visimp/core/stopwatch.h"
#include "visimp/core/bounding_box.h"
#include "visimp/core/errors.h"
#include "visimp/report/json.h"
#include "visimp/report/option_values.h"
#include "visimp/visibility/visibility.h"

namespace visimp::app {

namespace {

// OUT with "_<faces>" before the extension: the name of one level's snapshot.
std::string level_path(const std::string& out, std::size_t faces) {
  const std::filesystem::path p(out);
  return (p.parent_path() / (p.stem().string() + "_" + std::to_string(faces) + p.extension().string())).string();
}
}  // namespace

int run_simplify(const Args& args) {
  SimplifyOptions options;
  StreamOptions stream;
  SamplingOptions sampling;
  VisibilityOptions visibility_options;
  std::string method = "qb", targets_text;
  std::size_t levels = 0;
  bool weights_from_quality = false;
  double drop_hidden = -1;
  ArgParser parser(
      "visimp simplify IN OUT (--target N | --ratio R | --max-error E | --targets N,N,.. | --levels K) [options]",
      "Simplifies IN by quadric edge collapse and writes OUT atomically. --method qb: plain quadrics\n"
      "(Garland-Heckbert). --method vg: visibility-guided (Zhang & Turk): V(t)^2-weighted quadrics order\n"
      "the collapses, plain ones place the vertex; V is computed with the sampling options below, or\n"
      "read from IN's face quality (--weights-from-quality). --targets/--levels write OUT_<faces>.ext\n"
      "for every level from one collapse run. Non-manifold and misoriented parts are kept, locked.",
      2);
  parser.allow_output_flag(1);
  parser.add(describe_options(options));
  parser.add(option_spec("--method", "M", method, "qb (plain quadrics) or vg (visibility-guided)"));
  parser.add(option_spec("--targets", "N,N,..", targets_text, "face counts of the levels to write (one run)"));
  parser.add(option_spec("--levels", "K", levels,
                         "K levels log-spaced from 30% of the faces down to the target (default 2%)"));
  parser.add(
      switch_spec("--weights-from-quality", weights_from_quality, "take V from IN's face quality (no rendering)"));
  OptionSpec drop = option_spec("--drop-hidden", "T", drop_hidden,
                                "first remove faces with V <= T (never seen: T = 0, the value when T is left out)");
  drop.implicit_value = "0";
  drop.default_text = "off";
  parser.add(drop);
  parser.add(describe_options(sampling));
  parser.add(describe_options(visibility_options));
  parser.add(describe_options(stream, true));
  if (!parser.parse(args)) return 0;
  // 0 is the library's "unset"; typed by a user it is a mistake, and so are both at once.
  if (parser.given("--ratio") && !(options.target_ratio > 0 && options.target_ratio <= 1))
    throw UsageError("--ratio must be in (0, 1], got " + (std::ostringstream() << options.target_ratio).str());
  if (parser.given("--target") && options.target_faces == 0) throw UsageError("--target must be at least 1 face");
  if (parser.given("--target") && parser.given("--ratio")) throw UsageError("give --target or --ratio, not both");
  if (method != "qb" && method != "vg") throw UsageError("--method must be qb or vg, got '" + method + "'");
  options.method = method == "vg" ? SimplifyMethod::vg : SimplifyMethod::qb;
  const bool many = !targets_text.empty() || levels > 0;
  if (!targets_text.empty() && levels > 0) throw UsageError("give --targets or --levels, not both");
  if (levels > 64) throw UsageError("--levels must be in 1..64");
  if (!many && !parser.given("--target") && !parser.given("--ratio") && !parser.given("--max-error"))
    throw UsageError("give --target N, --ratio R, --max-error E, --targets N,N,.. or --levels K");
  if (!many) check_options(options);
  check_options(visibility_options);
  options.threads = static_cast<unsigned>(std::min<std::size_t>(sampling.threads, 1024));  // rendering and collapsing
  visibility_options.threads = options.threads;
  const std::string& in = parser.positionals()[0];
  const std::string& out = parser.positionals()[1];
  if (many && out == "-") throw UsageError("several levels need a file name for OUT, not '-'");
  const bool needs_visibility = options.method == SimplifyMethod::vg || drop_hidden >= 0;
  std::unique_ptr<Renderer> renderer;
  CameraSet cameras;
  if (needs_visibility && !weights_from_quality) {  // set up before any I/O, so bad flags fail first
    cameras = camera_set_from_spec(sampling.cameras);
    renderer = make_renderer(sampling.backend, render_options(sampling));
  }

  auto t = std::chrono::steady_clock::now();
  Mesh mesh = read_input(in, stream);
  require_faces(mesh, in, "simplify");
  const double read_seconds = seconds_since(t);
  const double diagonal = bounding_box(mesh).diagonal();

  // Visibility only when the request needs it: VG weights or dropping hidden faces.
  double visibility_seconds = 0;
  std::optional<Visibility> visibility;
  if (needs_visibility) {
    t = std::chrono::steady_clock::now();
    if (weights_from_quality) {
      try {
        visibility = visibility_from_face_quality(mesh);
      } catch (const InvalidMeshError& e) {
        throw InvalidMeshError(in + ": " + e.what());
      }
    } else {
      ProgressBar progress("visibility");
      visibility = compute_visibility(mesh, cameras, *renderer, visibility_options, &progress);
    }
    visibility_seconds = seconds_since(t);
  }
  std::optional<HiddenRemoval> removal;
  if (drop_hidden >= 0) {
    removal = drop_hidden_faces(mesh, visibility->face, drop_hidden);
    mesh = std::move(removal->mesh);
    visibility->face = removal->face_visibility;
  }
  if (options.method == SimplifyMethod::vg) options.face_visibility = visibility->face;

  std::vector<std::size_t> targets;
  if (!targets_text.empty()) targets = parse_count_list(targets_text, "--targets");
  if (levels > 0) {
    const double low = options.target_faces > 0
                           ? double(options.target_faces) / double(std::max<std::size_t>(mesh.num_faces(), 1))
                           : (options.target_ratio > 0 ? options.target_ratio : CompareOptions{}.min_ratio);
    const double high = CompareOptions{}.max_ratio;  // the same levels as visimp compare's
    targets = default_targets(mesh.num_faces(), levels, std::min(low, high), high);
  }

  std::vector<Simplified> results;
  {
    ProgressBar progress("simplify");
    if (many)
      results = simplify_levels(mesh, options, targets, &progress);
    else
      results.push_back(simplify(std::move(mesh), options, &progress));  // mesh is not read again
  }

  t = std::chrono::steady_clock::now();
  std::vector<std::string> outputs;
  for (const Simplified& s : results) {
    outputs.push_back(many ? level_path(out, s.mesh.num_faces()) : out);
    write_output(s.mesh, outputs.back(), in, stream);
  }
  const double write_seconds = seconds_since(t);

  std::ostream& report = out == "-" ? std::cerr : std::cout;
  if (stream.json) {
    JsonWriter json(report);
    json.begin_object()
        .field("command", "simplify")
        .field("input", in)
        .field("input_format", input_format_name(stream))
        .field("format_detected", input_format_detected(stream))
        .field("method", method)
        .field("quadric_weights", to_string(options.quadric_weights))
        .field("area_floor", options.area_floor)
        .field("bbox_diagonal", diagonal);
    // Every option the result depends on; the sampling's only when V was rendered.
    std::vector<OptionSpec> in_force = describe_options(options);
    in_force.push_back(option_spec("--method", "M", method, ""));
    if (renderer) {
      for (std::vector<OptionSpec> more : {describe_options(sampling), describe_options(visibility_options)})
        in_force.insert(in_force.end(), more.begin(), more.end());
    }
    json.key("options");
    write_option_values(json, in_force);
    if (visibility) {
      json.field("mesh_visibility", visibility->mesh).field("visibility_from_quality", weights_from_quality);
    }
    if (removal) {
      json.key("drop_hidden")
          .begin_object()
          .field("threshold", drop_hidden)
          .field("faces_removed", removal->faces_removed)
          .field("area_removed", removal->area_removed)
          .field("area_fraction_removed", removal->area_fraction_removed)
          .end_object();
    }
    json.key("levels").begin_array();
    for (std::size_t i = 0; i < results.size(); ++i) {
      const SimplifyResult& r = results[i].result;
      json.begin_object()
          .field("output", outputs[i])
          .field("faces_in", r.faces_in)
          .field("faces_out", r.faces_out)
          .field("vertices_in", r.vertices_in)
          .field("vertices_out", r.vertices_out)
          .field("target_faces", r.target_faces)
          .field("collapses", r.collapses)
          .field("parallel_collapses", r.parallel_collapses)
          .field("rejected_collapses", r.rejected_collapses)
          .field("requeued_edges", r.requeued_edges)
          .field("locked_vertices", r.locked_vertices)
          .field("dropped_faces", r.dropped_faces)
          .field("stop_reason", to_string(r.stop_reason))
          .field("max_error_relative", r.max_error)
          .field("max_error", r.max_error * diagonal)
          .field("seconds_simplify", r.seconds)
          .key("stage_seconds")
          .begin_object()
          .field("setup", r.stage_seconds.setup)
          .field("parallel_phase", r.stage_seconds.parallel_phase)
          .field("serial", r.stage_seconds.serial)
          .field("extract", r.stage_seconds.extract)
          .end_object()
          .end_object();
    }
    json.end_array();
    json.key("seconds")
        .begin_object()
        .field("read", read_seconds)
        .field("visibility", visibility_seconds)
        .field("simplify", results.back().result.seconds)
        .field("write", write_seconds)
        .end_object();
    json.end_object();
  } else {
    if (removal) {
      report << in << ": dropped " << removal->faces_removed << " hidden faces ("
             << 100.0 * removal->area_fraction_removed << "% of the area)\n";
    }
    for (std::size_t i = 0; i < results.size(); ++i) {
      const SimplifyResult& r = results[i].result;
      report << outputs[i] << ": " << r.faces_in << " -> " << r.faces_out << " faces (" << method << ", "
             << to_string(r.stop_reason) << "), max error " << r.max_error << " of the bbox diagonal, " << r.seconds
             << " s\n";
    }
  }
  return 0;
}

}  // namespace visimp::app
