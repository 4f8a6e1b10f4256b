// visimp metro / imgerr: error reports between two meshes (docs/metrics.md).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>

#include "cli.h"
#include "commands.h"
#include "visimp/core/errors.h"
#include "visimp/core/mesh_stats.h"
#include "visimp/metrics/bounded_hausdorff.h"
#include "visimp/metrics/image_error.h"
#include "visimp/metrics/surface_distance.h"
#include "visimp/render/image.h"
#include "visimp/report/json.h"

namespace visimp::app {
namespace {

void write_directed(JsonWriter& json, const char* name, const DirectedDistance& d, double diagonal) {
  json.key(name)
      .begin_object()
      .field("max", d.max)
      .field("mean", d.mean)
      .field("rms", d.rms)
      .field("max_relative", d.max / diagonal)
      .field("mean_relative", d.mean / diagonal)
      .field("rms_relative", d.rms / diagonal)
      .field("samples", d.samples)
      .field("face_samples", d.face_samples)
      .field("area", d.area);
  json.key("histogram_area_share").begin_array();
  for (double h : d.histogram) json.value(h);
  json.end_array().end_object();
}

void print_directed(std::ostream& out, const char* title, const DirectedDistance& d, double diagonal) {
  char line[256];
  out << title << "\n";
  std::snprintf(line, sizeof line, "  area %g, samples %zu (%zu on faces)\n", d.area, d.samples, d.face_samples);
  out << line;
  std::snprintf(line, sizeof line, "  max  %-12g (%g of the diagonal)\n  mean %-12g (%g)\n  RMS  %-12g (%g)\n", d.max,
                d.max / diagonal, d.mean, d.mean / diagonal, d.rms, d.rms / diagonal);
  out << line;
  out << "  histogram (share of the area per distance bin):\n";
  for (std::size_t i = 0; i < d.histogram.size(); ++i) {
    const double lo = d.max * double(i) / double(d.histogram.size()),
                 hi = d.max * double(i + 1) / double(d.histogram.size());
    std::snprintf(line, sizeof line, "    %11.5g .. %-11.5g %6.2f%%\n", lo, hi, 100.0 * d.histogram[i]);
    out << line;
  }
}

// Metro samples and searches faces with area: a mesh whose faces are all degenerate fails here,
// named, before any B is measured or any error map written.
void require_area(const Mesh& mesh, const std::string& path) {
  require_faces(mesh, path, "measure");
  for (const Face& f : mesh.faces)
    if (!is_degenerate(mesh, f)) return;
  throw InvalidMeshError((path == "-" ? std::string("<stdin>") : path) + ": no face with area to measure (" +
                         std::to_string(mesh.num_faces()) + " faces, all degenerate)");
}

// Standard input can be read once: at most one of the files may be "-".
void refuse_stdin_twice(const std::vector<std::string>& paths) {
  if (std::count(paths.begin(), paths.end(), "-") > 1)
    throw UsageError("'-' (standard input) can stand for one mesh only");
}

// FILE for one B; FILE_<k> (before the extension) for the k-th of several.
std::string numbered_path(const std::string& path, std::size_t k, std::size_t count) {
  if (count == 1) return path;
  const std::filesystem::path p(path);
  return (p.parent_path() / (p.stem().string() + "_" + std::to_string(k) + p.extension().string())).string();
}

// Outputs never replace an input: --error-ply B (or a numbered name that is some B) is refused
// before anything is written.
void refuse_overwriting_inputs(const std::string& output, const std::vector<std::string>& inputs) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (output == "-" || !fs::exists(output, ec)) return;
  for (const std::string& input : inputs)
    if (input != "-" && fs::equivalent(output, input, ec))
      throw UsageError(output + ": output would overwrite the input " + input);
}

void print_metro_json(JsonWriter& json, const std::string& path_a, const std::string& path_b, const SurfaceDistance& d,
                      const std::optional<HausdorffBounds>& bounds, bool visible) {
  json.begin_object().field("command", "metro").field("a", path_a).field("b", path_b);
  json.field("diagonal", d.diagonal).field("diagonal_of", "A");
  write_directed(json, "a_to_b", d.a_to_b, d.diagonal);
  write_directed(json, "b_to_a", d.b_to_a, d.diagonal);
  json.field("hausdorff", d.hausdorff).field("hausdorff_relative", d.hausdorff / d.diagonal);
  json.field("rms", d.rms).field("rms_relative", d.rms / d.diagonal);
  if (bounds) {
    json.key("hausdorff_bounds")
        .begin_object()
        .field("lower", bounds->lower)
        .field("upper", bounds->upper)
        .field("lower_relative", bounds->lower / d.diagonal)
        .field("upper_relative", bounds->upper / d.diagonal)
        .field("seconds", bounds->seconds)
        .end_object();
  }
  if (visible) {
    json.key("visible_a_to_b")
        .begin_object()
        .field("max", d.visible.max)
        .field("mean", d.visible.mean)
        .field("rms", d.visible.rms)
        .field("visible_area", d.visible.visible_area)
        .end_object();
  }
  json.key("seconds")
      .begin_object()
      .field("sampling", d.seconds_sampling)
      .field("index", d.seconds_index)
      .field("queries", d.seconds_queries)
      .field("total", d.seconds)
      .end_object();
  json.end_object();
}

void print_metro_text(std::ostream& out, const std::string& path_a, const Mesh& a, const std::string& path_b,
                      const Mesh& b, const SurfaceDistance& d, const std::optional<HausdorffBounds>& bounds,
                      bool visible) {
  out << "A: " << path_a << " (" << a.num_faces() << " faces)\nB: " << path_b << " (" << b.num_faces()
      << " faces)\nbounding-box diagonal of A: " << d.diagonal << "\n\n";
  print_directed(out, "A -> B", d.a_to_b, d.diagonal);
  print_directed(out, "B -> A", d.b_to_a, d.diagonal);
  out << "\nHausdorff distance: " << d.hausdorff << " (" << d.hausdorff / d.diagonal
      << " of the diagonal)\nsymmetric RMS:      " << d.rms << " (" << d.rms / d.diagonal << ")\n";
  if (bounds) {
    out << "certified Hausdorff: between " << bounds->lower << " and " << bounds->upper << " (" << bounds->seconds
        << " s)\n";
  }
  if (visible) {
    out << "visible A -> B:     max " << d.visible.max << ", mean " << d.visible.mean << ", RMS " << d.visible.rms
        << " (weights area x V, visible area " << d.visible.visible_area << ")\n";
  }
  out << "seconds: sampling " << d.seconds_sampling << ", index " << d.seconds_index << ", queries "
      << d.seconds_queries << ", total " << d.seconds << "\n";
}

}  // namespace

int run_metro(const Args& args) {
  SurfaceDistanceOptions options;
  StreamOptions stream;
  std::string error_ply, error_png, sampling = "random";
  double bound = 0;
  std::size_t threads = 0;
  ArgParser parser("visimp metro A B [B ...] [--samples N] [--visible] [--error-ply F] [--json]",
                   "Sampled distances between surfaces A and B in both directions (Metro, Cignoni et al. 1998):\n"
                   "max (Hausdorff), area-weighted mean and RMS, histogram; relative numbers are divided\n"
                   "by the bounding-box diagonal of A. With --visible, A's face quality is its visibility V\n"
                   "and A's samples are also weighted by it. With several B, A's samples and search tree are\n"
                   "made once and each B is measured against them (the same numbers as one call per B);\n"
                   "--json then prints an array of the one-B summaries, and --error-ply/--error-png F write\n"
                   "F_1.ext, F_2.ext, .. (k-th B). Every B is read before anything is measured.",
                   2, std::numeric_limits<std::size_t>::max());
  parser.add(
      option_spec("--samples", "N", options.samples, "face samples per direction (0: 10 x the larger face count)"));
  parser.add(option_spec("--edge-samples", "N", options.edge_samples,
                         "edge samples per direction (0: the larger face count)"));
  parser.add(option_spec("--bins", "N", options.histogram_bins, "histogram bins over [0, max]"));
  parser.add(option_spec("--threads", "N", threads, "worker threads, 0 = one per hardware thread"));
  bool visible = false;
  parser.add(switch_spec("--visible", visible, "also report A->B weighted by V (A's face quality)"));
  parser.add(option_spec("--density", "D", options.density, "face samples per unit area (replaces --samples)"));
  parser.add(option_spec("--sampling", "MODE", sampling,
                         "random (Monte Carlo) or stratified (one point per cell of a k x k split)"));
  parser.add(option_spec("--bound", "T", bound,
                         "also certify the Hausdorff distance within T x the diagonal of A (CGAL bounded-error)"));
  parser.add(
      option_spec("--error-ply", "FILE", error_ply, "write A with each vertex's distance to B as vertex quality"));
  parser.add(option_spec("--error-png", "FILE", error_png,
                         "picture of A coloured by its faces' distance to B (blue 0 .. red max)"));
  parser.add(describe_options(stream, false));
  if (!parser.parse(args)) return 0;
  if (options.histogram_bins == 0 || options.histogram_bins > 10000) throw UsageError("--bins must be in 1..10000");
  options.threads = static_cast<int>(std::min<std::size_t>(threads, 1024));
  options.vertex_errors = !error_ply.empty() || !error_png.empty();
  if (sampling == "stratified")
    options.sampling = FaceSampling::stratified;
  else if (sampling != "random")
    throw UsageError("--sampling " + sampling + ": expected random or stratified");
  if (!(options.density >= 0) || !std::isfinite(options.density))
    throw UsageError("--density must be a finite number >= 0");
  if (!(bound >= 0) || !std::isfinite(bound)) throw UsageError("--bound must be a finite number >= 0");
  const std::vector<std::string>& paths = parser.positionals();
  const std::string& path_a = paths[0];
  const std::size_t count = paths.size() - 1;
  refuse_stdin_twice(paths);
  if (count > 1 && (error_ply == "-" || error_png == "-"))
    throw UsageError("--error-ply/--error-png - takes one B (several B write FILE_1, FILE_2, ..)");
  for (std::size_t k = 1; k <= count; ++k) {
    if (!error_ply.empty()) refuse_overwriting_inputs(numbered_path(error_ply, k, count), paths);
    if (!error_png.empty()) refuse_overwriting_inputs(numbered_path(error_png, k, count), paths);
  }
  const Mesh a = read_input(path_a, stream);
  require_area(a, path_a);
  if (visible) {
    if (a.face_quality.size() != a.num_faces())
      throw InvalidMeshError(path_a + ": --visible needs V as face quality (a 'visimp visibility' output)");
    options.face_visibility = a.face_quality;
  }
  // Every B read first: a B that cannot be read, or has no face with area, fails the call before
  // anything is written.
  std::vector<Mesh> results;
  for (std::size_t k = 1; k <= count; ++k) {
    results.push_back(read_input(paths[k], stream));
    require_area(results.back(), paths[k]);
  }
  // With several B, A's samples and tree are kept between them; one B is one surface_distance(),
  // which frees them before the bound and the pictures (the same numbers either way).
  std::optional<SurfaceDistanceReference> reference;
  if (count > 1) reference.emplace(a);
  // Printed once every B has been measured: a B that fails leaves no partial report on stdout.
  std::ostringstream report;
  JsonWriter json(report);
  if (stream.json && count > 1) json.begin_array();
  for (std::size_t k = 1; k <= count; ++k) {
    const Mesh& b = results[k - 1];
    const SurfaceDistance d = reference ? reference->distance_to(b, options) : surface_distance(a, b, options);
    std::optional<HausdorffBounds> bounds;
    if (bound > 0) bounds = bounded_hausdorff(a, b, bound * d.diagonal, d.hausdorff);
    if (!error_ply.empty()) {
      Mesh map = a;
      map.vertex_quality = d.vertex_error;
      write_output(map, numbered_path(error_ply, k, count), path_a, stream);
    }
    if (!error_png.empty()) {
      std::vector<Rgb> colors(a.num_faces());
      for (std::size_t f = 0; f < colors.size(); ++f)
        colors[f] = heat_color(d.a_to_b.max > 0 ? d.face_error[f] / d.a_to_b.max : 0.0);
      write_png(numbered_path(error_png, k, count), render_face_colors(a, colors, kPictureSize));
    }
    if (stream.json) {
      print_metro_json(json, path_a, paths[k], d, bounds, visible);
    } else {
      if (k > 1) report << "\n";
      print_metro_text(report, path_a, a, paths[k], b, d, bounds, visible);
    }
  }
  if (stream.json && count > 1) json.end_array();
  std::cout << report.str();
  return 0;
}

int run_imgerr(const Args& args) {
  ImageErrorOptions options;
  StreamOptions stream;
  std::size_t resolution = static_cast<std::size_t>(options.resolution), threads = 0,
              supersample = static_cast<std::size_t>(options.supersample);
  ArgParser parser("visimp imgerr A B [B ...] [--resolution R] [--supersample S] [--diff-prefix P] [--json]",
                   "Image RMS error (Zhang & Turk 2002, eq. 5.11) between A and B rendered flat-shaded from\n"
                   "the 20 vertices of a dodecahedron around A's bounding sphere (A's and B's when B reaches\n"
                   "outside it). With several B,\n"
                   "A's views are drawn once and each B is measured against them (the same numbers as one\n"
                   "call per B); --json then prints an array of the one-B summaries. Every B is read before\n"
                   "anything is measured.",
                   2, std::numeric_limits<std::size_t>::max());
  parser.add(option_spec("--resolution", "R", resolution, "view width and height in pixels, 16..8192"));
  parser.add(option_spec("--threads", "N", threads, "worker threads, 0 = one per hardware thread"));
  parser.add(option_spec("--supersample", "S", supersample,
                         "samples per pixel side, averaged (box filter), 1..8; 1: point sampling"));
  parser.add(
      option_spec("--diff-prefix", "P", options.difference_prefix,
                  "write P0.png..P19.png: |I_A - I_B| in the red channel (several B: P<k>_0.png.., k = 1, 2, ..)"));
  parser.add(describe_options(stream, false));
  if (!parser.parse(args)) return 0;
  check_pixels(resolution, "--resolution");
  options.resolution = static_cast<int>(resolution);
  if (supersample < 1 || supersample > 8) throw UsageError("--supersample must be in 1..8");
  options.supersample = static_cast<int>(supersample);
  options.threads = static_cast<unsigned>(std::min<std::size_t>(threads, 1024));
  const std::vector<std::string>& paths = parser.positionals();
  const std::string& path_a = paths[0];
  const std::size_t count = paths.size() - 1;
  refuse_stdin_twice(paths);
  const Mesh a = read_input(path_a, stream);
  // Every B read first: a B that cannot be read fails the call before anything is written.
  std::vector<Mesh> results;
  for (std::size_t k = 1; k <= count; ++k) results.push_back(read_input(paths[k], stream));
  // With several B, A's views are drawn once; one B is one image_error() call, whose seconds
  // count A's drawing too.
  std::optional<ImageErrorReference> reference;
  if (count > 1) reference.emplace(a, options);
  // Printed once every B has been measured: a B that fails leaves no partial report on stdout.
  std::ostringstream report;
  JsonWriter json(report);
  if (stream.json && count > 1) json.begin_array();
  for (std::size_t k = 1; k <= count; ++k) {
    const std::string& path_b = paths[k];
    const std::string& prefix = options.difference_prefix;
    const ImageError e =
        reference ? reference->error_to(results[k - 1], prefix.empty() ? prefix : prefix + std::to_string(k) + "_")
                  : image_error(a, results[0], options);
    if (stream.json) {
      json.begin_object().field("command", "imgerr").field("a", path_a).field("b", path_b);
      json.field("resolution", static_cast<std::int64_t>(e.resolution))
          .field("supersample", static_cast<std::int64_t>(e.supersample))
          .field("views", e.views);
      json.field("rms", e.rms).field("rms_per_pixel", e.rms_per_pixel);
      json.key("view_rms_per_pixel").begin_array();
      for (double v : e.view_rms) json.value(v);
      json.end_array().field("seconds", e.seconds).end_object();
    } else {
      if (count > 1) report << "B: " << path_b << "\n";
      report << "image RMS error (eq. 5.11): " << e.rms << "\nper-pixel RMS: " << e.rms_per_pixel << " of 255 ("
             << e.views << " views at " << e.resolution << "x" << e.resolution << ", " << e.supersample << "x"
             << e.supersample << " samples per pixel, " << e.seconds << " s)\n";
    }
  }
  if (stream.json && count > 1) json.end_array();
  std::cout << report.str();
  return 0;
}

}  // namespace visimp::app
