// visimp visibility / visibility-merge / visibility-study: the visibility measure from the
// command line (docs/visibility.md).
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>

#include "backends.h"
#include "cli.h"
#include "commands.h"
#include "visimp/core/errors.h"
#include "visimp/core/stopwatch.h"
#include "visimp/io/atomic_file.h"
#include "visimp/report/json.h"
#include "visimp/report/option_values.h"
#include "visimp/report/svg_plot.h"
#include "visimp/visibility/orient.h"
#include "visimp/visibility/visibility.h"
#include "visimp/visibility/visibility_study.h"

namespace visimp::app {
namespace {

// "a:b" → [a, b); empty → the whole set.
std::pair<std::size_t, std::size_t> parse_camera_range(const std::string& text, std::size_t cameras) {
  if (text.empty()) return {0, cameras};
  const std::size_t colon = text.find(':');
  if (colon == std::string::npos) throw UsageError("--camera-range expects FIRST:LAST, got '" + text + "'");
  const std::size_t first = parse_count(text.substr(0, colon), "--camera-range FIRST");
  const std::size_t last = parse_count(text.substr(colon + 1), "--camera-range LAST");
  if (first >= last || last > cameras) {
    throw UsageError("--camera-range " + text + " must satisfy FIRST < LAST <= " + std::to_string(cameras));
  }
  return {first, last};
}

void require_ply(const std::string& path, const StreamOptions& stream) {
  if (path == "-" && (stream.output_format.empty() ? stream.format : stream.output_format) != "ply") {
    throw UsageError("writing '-' needs --format ply: only PLY carries V as face and vertex quality");
  }
  if (path != "-" && stream.output_format.empty() && format_from_path(path) != Format::ply) {
    throw UsageError(path + ": only PLY carries V as face and vertex quality; name the output .ply");
  }
}

void write_stats(JsonWriter& json, const VisibilityStats& s) {
  json.field("faces_in", s.input_faces)
      .field("faces_refined", s.refined_faces)
      .field("refinement_rounds", static_cast<std::int64_t>(s.refinement_rounds))
      .field("max_edge_length", s.max_edge_length)
      .field("cameras", s.cameras)
      .field("resolution", static_cast<std::int64_t>(s.resolution))
      .field("back_faces_culled", s.back_faces_culled)
      .field("one_sided_faces", s.one_sided_faces)
      .field("two_sided_faces", s.two_sided_faces)
      .field("seen_from_behind_faces", s.seen_from_behind)
      .field("degenerate_faces", s.degenerate_faces)
      .field("unfaced_faces", s.unfaced_faces)
      .field("hidden_faces", s.hidden_faces)
      .field("hidden_area_fraction", s.hidden_area_fraction);
}

// V as the mesh's face and vertex quality, in place: a copy of a 14M-face mesh costs
// a third of a second and 340 MB.
void attach_visibility(Mesh& mesh, const Visibility& v) {
  mesh.face_quality = v.face;
  mesh.vertex_quality = v.vertex;
}

}  // namespace

std::pair<std::size_t, std::size_t> camera_slice(std::size_t first, std::size_t last, int rank, int ranks) {
  const std::size_t n = last - first, r = static_cast<std::size_t>(rank), k = static_cast<std::size_t>(ranks);
  return {first + n * r / k, first + n * (r + 1) / k};
}

int run_visibility(const Args& args, CameraSplit* split) {
  VisibilityOptions options;
  SamplingOptions sampling;
  StreamOptions stream;
  std::string png, tally_path, range_text;
  std::size_t png_size = kPictureSize;
  ArgParser parser(
      "visimp visibility IN [OUT.ply] [--cameras SET] [--resolution R] [--backend raster|osmesa] [options]",
      "Computes the visibility V(t) of every face of IN (Zhang & Turk 2002) and writes it to OUT.ply as\n"
      "face and vertex quality. With --camera-range and --tally, computes one slice of the cameras for\n"
      "'visimp visibility-merge' instead (OUT is then optional).",
      1, 2);
  parser.allow_output_flag(1);
  parser.add(describe_options(sampling));
  parser.add(describe_options(options));
  parser.add(option_spec("--png", "FILE", png, "also write a picture of V (the paper's colour scale) from a 3/4 view"));
  parser.add(option_spec("--png-size", "PX", png_size, "size of that picture, 16..8192"));
  parser.add(option_spec("--camera-range", "A:B", range_text, "only cameras A..B-1 of the set"));
  parser.add(option_spec("--tally", "FILE", tally_path, "write the slice's tallies to FILE"));
  parser.add(describe_options(stream, true));
  if (!parser.parse(args)) return 0;
  options.threads = render_options(sampling).threads;  // preparing and finishing, as rendering
  check_options(options);
  const std::string& in = parser.positionals()[0];
  const std::string out = parser.positionals().size() > 1 ? parser.positionals()[1] : "";
  if (out.empty() && tally_path.empty()) throw UsageError("give OUT.ply, or --tally FILE for a slice");
  if (!out.empty()) require_ply(out, stream);
  check_pixels(png_size, "--png-size");
  const CameraSet cameras = camera_set_from_spec(sampling.cameras);
  const auto [first, last] = parse_camera_range(range_text, cameras.size());
  const int ranks = split ? split->ranks() : 1;
  const bool root = !split || split->rank() == 0;
  if (static_cast<std::size_t>(ranks) > last - first)
    throw UsageError(std::to_string(ranks) + " processes for " + std::to_string(last - first) +
                     " cameras: use at most one process per camera");
  const auto [my_first, my_last] = split ? camera_slice(first, last, split->rank(), ranks) : std::pair{first, last};
  const auto renderer = make_renderer(sampling.backend, render_options(sampling));

  const auto start = std::chrono::steady_clock::now();
  Mesh mesh = read_input(in, stream);
  require_faces(mesh, in, "measure");
  const double read_seconds = seconds_since(start);
  const VisibilityJob job(mesh, renderer->resolution(), options);
  auto t = std::chrono::steady_clock::now();
  VisibilityTally tally;
  {
    std::optional<ProgressBar> progress;
    if (root) progress.emplace("visibility");  // one bar, for process 0's slice
    tally = job.render(cameras, my_first, my_last, *renderer, progress ? &*progress : nullptr);
  }
  // The tallies are integer sums, so the merged one, and V, are the same bytes as one process's.
  if (split) tally = split->gather(tally);
  if (!root) return 0;
  const double render_seconds = seconds_since(t);
  double write_seconds = 0, png_seconds = 0;
  if (!tally_path.empty()) {
    t = std::chrono::steady_clock::now();
    tally.write(tally_path);
    write_seconds += seconds_since(t);
  }
  std::optional<Visibility> visibility;
  if (!out.empty()) {
    visibility = job.finish(tally);
    visibility->stats.seconds_render = render_seconds;
    t = std::chrono::steady_clock::now();
    attach_visibility(mesh, *visibility);  // the job is done with the mesh: finish() was its last use
    write_output(mesh, out, in, stream);
    write_seconds += seconds_since(t);
    if (!png.empty()) {
      t = std::chrono::steady_clock::now();
      write_png(png, render_visibility_map(mesh, visibility->face, static_cast<int>(png_size)));
      png_seconds = seconds_since(t);
    }
  }
  const VisibilityStats& s = visibility ? visibility->stats : job.stats();
  std::ostream& report = out == "-" ? std::cerr : std::cout;
  if (stream.json) {
    JsonWriter json(report);
    json.begin_object()
        .field("command", "visibility")
        .field("input", in)
        .field("input_format", input_format_name(stream))
        .field("format_detected", input_format_detected(stream))
        .field("output", out);
    if (!tally_path.empty()) json.field("tally", tally_path);
    json.field("backend", renderer->name()).field("camera_set", cameras.name);
    json.field("camera_first", first).field("camera_last", last).field("fractional", options.fractional);
    json.field("trust_winding", options.trust_winding).field("processes", ranks);
    std::vector<OptionSpec> in_force = describe_options(sampling);  // every option V depends on
    const std::vector<OptionSpec> measure = describe_options(options);
    in_force.insert(in_force.end(), measure.begin(), measure.end());
    json.key("options");
    write_option_values(json, in_force);
    write_stats(json, s);
    if (visibility) json.field("mesh_visibility", visibility->mesh);
    json.key("seconds")
        .begin_object()
        .field("read", read_seconds)
        .field("prepare", s.seconds_prepare)
        .field("orient", s.seconds_orient)
        .field("refine", s.seconds_refine)
        .field("scene", s.seconds_scene)
        .field("render", render_seconds)
        .field("aggregate", s.seconds_aggregate)
        .field("png", png_seconds)
        .field("write", write_seconds)
        .field("total", seconds_since(start))
        .end_object();
    json.end_object();
  } else {
    report << in << ": ";
    if (visibility) report << "V(M) = " << visibility->mesh << ", ";
    report << s.input_faces << " faces (" << s.refined_faces << " after refinement), cameras " << first << ".." << last
           << " of " << cameras.size() << ", prepare " << s.seconds_prepare << " s, render " << render_seconds << " s\n";
  }
  return 0;
}

int run_orient(const Args& args) {
  VisibilityOptions options;
  SamplingOptions sampling;
  StreamOptions stream;
  OrientOptions orient;
  ArgParser parser("visimp orient IN OUT [--cameras SET] [--resolution R] [--both-sides T] [--json]",
                   "Writes IN with every face wound so that its front is the side the cameras see\n"
                   "(visibility from both sides of every face). Faces seen from both sides are left as\n"
                   "they are; faces no camera sees follow their surface (outward when it is closed).",
                   2, 2);
  parser.allow_output_flag(1);
  parser.add(describe_options(sampling));
  parser.add(describe_options(options));
  parser.add(option_spec("--both-sides", "T", orient.both_sides_threshold,
                         "a face whose two sides both have V > T is left as it is, [0, 1)"));
  parser.add(describe_options(stream, true));
  if (!parser.parse(args)) return 0;
  options.threads = render_options(sampling).threads;  // preparing and finishing, as rendering
  orient.threads = options.threads;                    // and the winding patches
  check_options(options);
  if (options.trust_winding) throw UsageError("--trust-winding measures one side only: orient needs both");
  const std::string& in = parser.positionals()[0];
  const std::string& out = parser.positionals()[1];
  const CameraSet cameras = camera_set_from_spec(sampling.cameras);
  const auto renderer = make_renderer(sampling.backend, render_options(sampling));
  const auto start = std::chrono::steady_clock::now();
  const Mesh mesh = read_input(in, stream);
  require_faces(mesh, in, "orient");
  Visibility visibility;
  {
    ProgressBar progress("visibility");
    visibility = compute_visibility(mesh, cameras, *renderer, options, &progress);
  }
  const OrientResult result = orient_by_visibility(mesh, visibility, orient);
  write_output(result.mesh, out, in, stream);
  std::ostream& report = out == "-" ? std::cerr : std::cout;
  if (stream.json) {
    JsonWriter json(report);
    json.begin_object()
        .field("command", "orient")
        .field("input", in)
        .field("input_format", input_format_name(stream))
        .field("format_detected", input_format_detected(stream))
        .field("output", out);
    json.field("faces", mesh.num_faces())
        .field("reversed_faces", result.reversed)
        .field("seen_from_both_sides_faces", result.seen_from_both_sides)
        .field("never_seen_faces", result.never_seen)
        .field("mesh_visibility", visibility.mesh)
        .field("cameras", cameras.size())
        .field("resolution", static_cast<std::int64_t>(renderer->resolution()))
        .field("seconds", seconds_since(start));
    json.end_object();
  } else {
    report << in << ": " << result.reversed << " of " << mesh.num_faces() << " faces reversed, "
           << result.seen_from_both_sides << " seen from both sides left as they were, " << result.never_seen
           << " never seen (wound like their surface)\n";
  }
  return 0;
}

int run_visibility_merge(const Args& args) {
  std::string out, mesh_path;
  StreamOptions stream;
  ArgParser parser("visimp visibility-merge PART.bin... -o OUT [--mesh IN]",
                   "Adds tallies of disjoint camera slices. OUT is a merged tally, or, with --mesh IN (the\n"
                   "mesh the slices were computed for), a PLY with V as quality - bit for bit what one\n"
                   "'visimp visibility' run over all cameras writes.",
                   1, 100000);
  parser.add(option_spec("-o", "OUT", out, "the merged tally, or the mesh with V when --mesh is given"));
  parser.add(option_spec("--mesh", "IN", mesh_path, "the input mesh of the slices"));
  parser.add(describe_options(stream, true));
  if (!parser.parse(args)) return 0;
  if (out.empty()) throw UsageError("-o OUT is required");
  const auto start = std::chrono::steady_clock::now();
  VisibilityTally merged = VisibilityTally::read(parser.positionals()[0]);
  for (std::size_t i = 1; i < parser.positionals().size(); ++i) {
    try {
      merged.merge(VisibilityTally::read(parser.positionals()[i]));
    } catch (const UsageError& e) {
      throw UsageError(parser.positionals()[i] + ": " + e.what());
    }
  }
  std::optional<Visibility> visibility;
  if (mesh_path.empty()) {
    merged.write(out);
  } else {
    require_ply(out, stream);
    Mesh mesh = read_input(mesh_path, stream);
    const VisibilityJob job(mesh, static_cast<int>(merged.key.resolution), options_of(merged.key));
    if (job.mesh_hash() != merged.key.mesh_hash) {
      throw UsageError(mesh_path + ": not the mesh these tallies were computed for");
    }
    visibility = job.finish(merged);
    attach_visibility(mesh, *visibility);
    write_output(mesh, out, mesh_path, stream);
  }
  std::ostream& report = out == "-" ? std::cerr : std::cout;
  if (stream.json) {
    JsonWriter json(report);
    json.begin_object().field("command", "visibility-merge").field("output", out);
    json.field("parts", parser.positionals().size()).field("cameras", merged.key.camera_count);
    json.field("camera_ranges", merged.describe_ranges()).field("complete", merged.complete());
    if (visibility) json.field("mesh_visibility", visibility->mesh);
    json.field("seconds", seconds_since(start));
    json.end_object();
  } else {
    report << "merged " << parser.positionals().size() << " tallies: cameras " << merged.describe_ranges() << " of "
           << merged.key.camera_count;
    if (visibility) report << ", V(M) = " << visibility->mesh;
    report << "\n";
  }
  return 0;
}

int run_visibility_study(const Args& args) {
  VisibilityOptions options;
  SamplingOptions sampling;
  StreamOptions stream;
  std::string csv_path, svg_path;
  std::size_t max_level = 5;
  ArgParser parser("visimp visibility-study IN [--csv FILE] [--svg FILE] [--json]",
                   "Computes V with 6, 18, 66, 258, 1026 cameras and compares each with 4098 cameras\n"
                   "(octahedron levels 0..4 against level 5): the area-weighted mean |V - V_ref| and the\n"
                   "seconds each took - Fig. 3 of Zhang & Turk 2002. CSV on stdout unless --json.",
                   1);
  parser.add(describe_options(sampling), {"--cameras"});  // the study picks its camera sets itself (--max-level)
  parser.add(describe_options(options));
  parser.add(option_spec("--max-level", "K", max_level, "reference octahedron level, 1..5"));
  parser.add(option_spec("--csv", "FILE", csv_path, "also write the table as CSV"));
  parser.add(option_spec("--svg", "FILE", svg_path, "plot error against seconds (log axes)"));
  parser.add(describe_options(stream, false));
  if (!parser.parse(args)) return 0;
  options.threads = render_options(sampling).threads;  // preparing and finishing, as rendering
  check_options(options);
  if (max_level < 1 || max_level > 5) throw UsageError("--max-level must be in 1..5");
  const std::string& in = parser.positionals()[0];
  const Mesh mesh = read_input(in, stream);
  require_faces(mesh, in, "measure");
  const auto renderer = make_renderer(sampling.backend, render_options(sampling));

  std::vector<VisibilityStudyRow> rows;
  {
    ProgressBar progress("visibility-study");
    rows = visibility_study(mesh, *renderer, options, static_cast<int>(max_level), &progress);
  }

  std::ostringstream csv;
  csv << "level,cameras,seconds,mesh_visibility,mean_abs_error_vs_" << rows.back().cameras << "\n";
  for (const VisibilityStudyRow& r : rows)
    csv << r.level << "," << r.cameras << "," << r.seconds << "," << r.mesh_visibility << "," << r.mean_abs_error
        << "\n";
  if (!csv_path.empty()) {
    AtomicFileWriter file(csv_path);
    file.stream() << csv.str();
    file.commit();
  }
  if (!svg_path.empty()) {
    SvgPlot plot;
    plot.title = "Visibility error vs time: " + in;
    plot.x_label = "seconds";
    plot.y_label = "mean |V - V(" + std::to_string(rows.back().cameras) + " cameras)|";
    plot.log_x = plot.log_y = true;
    PlotSeries series;
    series.label = renderer->name() + " " + std::to_string(sampling.resolution) + "px";
    for (std::size_t i = 0; i + 1 < rows.size(); ++i) {
      series.points.emplace_back(rows[i].seconds, rows[i].mean_abs_error);
      series.point_labels.push_back(std::to_string(rows[i].cameras));
    }
    plot.series.push_back(series);
    AtomicFileWriter file(svg_path);
    plot.write(file.stream());
    file.commit();
  }
  if (stream.json) {
    JsonWriter json(std::cout);
    json.begin_object()
        .field("command", "visibility-study")
        .field("input", in)
        .field("input_format", input_format_name(stream))
        .field("format_detected", input_format_detected(stream))
        .field("backend", renderer->name());
    json.field("resolution", sampling.resolution).field("reference_cameras", rows.back().cameras);
    json.key("rows").begin_array();
    for (const VisibilityStudyRow& r : rows) {
      json.begin_object()
          .field("level", static_cast<std::int64_t>(r.level))
          .field("cameras", r.cameras)
          .field("seconds", r.seconds)
          .field("mesh_visibility", r.mesh_visibility)
          .field("mean_abs_error", r.mean_abs_error)
          .end_object();
    }
    json.end_array().end_object();
  } else {
    std::cout << csv.str();
  }
  return 0;
}

}  // namespace visimp::app
