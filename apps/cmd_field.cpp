// visimp field build / query / study: the visibility field of Blais & Poulin from the
// command line (docs/field.md).
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <optional>

#include "cli.h"
#include "commands.h"
#include "visimp/core/errors.h"
#include "visimp/core/face_subset.h"
#include "visimp/field/field.h"
#include "visimp/field/field_study.h"
#include "visimp/field/resample.h"
#include "visimp/io/atomic_file.h"
#include "visimp/report/json.h"

namespace visimp::app {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

constexpr const char* kFieldUsage =
    "usage: visimp field build|query|study ...\n"
    "\n"
    "  build IN [-o F.vfd]              cells per object, six slabs, 81 rays per sample (Blais & Poulin)\n"
    "  query F.vfd --view X,Y,Z         the cells (and faces) to draw from a viewpoint\n"
    "  study IN [-o DIR]                cells, faces, missed pixels and frame times along camera paths\n"
    "\n"
    "'visimp field COMMAND --help' describes each.\n";

std::string default_field_output(const std::string& in) {
  if (in == "-") throw UsageError("reading '-' needs -o F.vfd");
  return (std::filesystem::path(in).replace_extension(".vfd")).string();
}

// --cells and --groups-from-quality, shared by build and study.
void apply_cell_choice(const std::string& mode, bool groups_from_quality, const Mesh& mesh, const std::string& in,
                       CellOptions& cells) {
  cells.mode = parse_cell_mode(mode);
  if (!groups_from_quality) return;
  if (!mesh.has_face_quality()) throw UsageError("--groups-from-quality: " + in + " has no face quality");
  cells.face_objects.resize(mesh.num_faces());
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const float q = mesh.face_quality[f];
    if (!(q >= 0 && q < 16777216.0f) || q != std::floor(q))
      throw UsageError("--groups-from-quality: face " + std::to_string(f) + " of " + in + " has quality " +
                       std::to_string(q) + ", not a group number 0..2^24");
    cells.face_objects[f] = static_cast<std::uint32_t>(q);
  }
}

int run_build(const Args& args) {
  FieldOptions options;
  StreamOptions stream;
  std::string out, mode = "object";
  bool groups = false;
  ArgParser parser("visimp field build IN [-o F.vfd] [--grid N] [--uv N] [--st N] [--ids N] [--slabs 6|1] [options]",
                   "Divides each object of IN (a connected component, or a group with --groups-from-quality) into\n"
                   "its own grid of cells, places one slab per side of the scene's box and casts 81 rays per\n"
                   "(u, v, s, t) sample, keeping the cell ids hit most often. Writes F.vfd (default: IN with .vfd).",
                   1, 1);
  parser.add(option_spec("-o", "F.vfd", out, "the field file (docs/field.md)"));
  parser.add(describe_options(options));
  parser.add(option_spec("--cells", "object|polygon|scene", mode,
                         "a grid per object, one cell per face, or one grid over the scene"));
  parser.add(switch_spec("--groups-from-quality", groups, "objects are the faces' quality values (group numbers)"));
  parser.add(describe_options(stream, false));
  if (!parser.parse(args)) return 0;
  const std::string& in = parser.positionals()[0];
  if (out.empty()) out = default_field_output(in);
  if (out == in) throw UsageError(out + " is the input; choose another output name");
  const Mesh mesh = read_input(in, stream);
  require_faces(mesh, in, "build a visibility field for");
  apply_cell_choice(mode, groups, mesh, in, options.cells);
  check_options(options, mesh.num_faces());

  VisibilityField field;
  {
    ProgressBar progress("sampling");
    field = build_field(mesh, options, &progress);
  }
  const auto t = Clock::now();
  const FieldFileSizes sizes = write_field_file(field, out);
  const double write_seconds = seconds_since(t);
  if (stream.json) {
    JsonWriter json(std::cout);
    json.begin_object().field("command", "field build").field("input", in);
    json.field("input_format", input_format_name(stream)).field("format_detected", input_format_detected(stream));
    json.field("output", out).field("faces", mesh.num_faces());
    json.field("cell_mode", cell_mode_name(field.options.cells.mode))
        .field("grid", static_cast<std::int64_t>(options.cells.grid));
    json.field("objects", field.cells.objects).field("cells", field.cells.num_cells());
    json.field("slabs", field.slabs.size()).field("layers", static_cast<std::int64_t>(options.layers));
    json.field("uv", static_cast<std::int64_t>(options.uv)).field("st", static_cast<std::int64_t>(options.st));
    json.field("ids", static_cast<std::int64_t>(options.ids)).field("rays", field.rays);
    json.key("bytes")
        .begin_object()
        .field("file", sizes.file_bytes)
        .field("samples_raw", sizes.raw_sample_bytes)
        .field("samples_coded", sizes.coded_sample_bytes)
        .field("compression_ratio", sizes.compression_ratio())
        .end_object();
    json.key("seconds").begin_object().field("build", field.seconds_build).field("write", write_seconds).end_object();
    json.end_object();
    std::cout << '\n';
  } else {
    std::cout << out << ": " << field.cells.num_cells() << " cells in " << field.cells.objects << " objects, "
              << field.slabs.size() << " slabs x " << options.layers << " layers of " << options.uv << "^2 x "
              << options.st << "^2 samples, " << options.ids << " ids each\n"
              << "  " << field.rays << " rays in " << std::setprecision(3) << field.seconds_build << " s; samples "
              << sizes.raw_sample_bytes << " bytes, coded " << sizes.coded_sample_bytes << " (ratio "
              << sizes.compression_ratio() << "), file " << sizes.file_bytes << " bytes\n";
  }
  return 0;
}

int run_query(const Args& args) {
  std::string view_text, look_text, interp = "none", mesh_path, out;
  double fov = 60;
  std::size_t resolution = 480;
  ResampleOptions resample;
  bool json_out = false;
  StreamOptions stream;
  ArgParser parser(
      "visimp field query F.vfd --view X,Y,Z [--look X,Y,Z] [--fov DEG] [--resolution R] "
      "[--subsample K] [--interp none|uv|st|uvst] [--mesh IN -o CULLED.ply] [--json]",
      "Resamples the field for a perspective viewer (Blais & Poulin Fig. 4): rays from --view through\n"
      "1 of K pixels, each marking the cells its (u, v, s, t) sample holds. Prints the marked cells, or\n"
      "with --mesh and -o writes the faces of the marked cells (input order, face property source_face).",
      1, 1);
  parser.add(option_spec("--view", "X,Y,Z", view_text, "viewpoint in mesh coordinates (required)"));
  parser.add(option_spec("--look", "X,Y,Z", look_text, "point looked at (default: the scene's centre)"));
  parser.add(option_spec("--fov", "DEG", fov, "field of view across the image, in (0, 170]"));
  parser.add(option_spec("--resolution", "R", resolution, "image width and height in pixels, 16..8192"));
  parser.add(describe_options(resample));
  parser.add(option_spec("--interp", "none|uv|st|uvst", interp, "post-filtering: also the neighbouring samples"));
  parser.add(option_spec("--mesh", "IN", mesh_path, "the mesh the field was built from (checked by its hash)"));
  parser.add(option_spec("-o", "CULLED.ply", out, "write the faces of the marked cells (needs --mesh; '-' = stdout)"));
  parser.add(switch_spec("--json", json_out, "machine-readable summary"));
  parser.add(option_spec("--format", "FMT", stream.format, "format of '-' (ply, obj, off, stl)"));
  if (!parser.parse(args)) return 0;
  if (view_text.empty()) throw UsageError("--view X,Y,Z is required");
  if (!out.empty() && mesh_path.empty()) throw UsageError("-o needs --mesh IN: the field holds no geometry");
  check_pixels(resolution, "--resolution");
  if (!(fov > 0 && fov <= 170)) throw UsageError("--fov must be in (0, 170] degrees");
  resample.interpolation = parse_interpolation(interp);
  check_options(resample);
  const Vec3 eye = parse_point(view_text, "--view");
  const std::string& path = parser.positionals()[0];
  const VisibilityField field = read_field_file(path);
  const Vec3 look = look_text.empty() ? field.box.center() : parse_point(look_text, "--look");
  if (!(norm(look - eye) > 1e-12 * std::max(1.0, field.box.diagonal())))
    throw UsageError("--look must differ from --view (no direction to look in)");
  if (field.inside_solid(eye))
    throw UsageError("--view " + view_text + " is inside the geometry (a solid part of the scene)");
  const PerspectiveView view =
      PerspectiveView::looking_at(eye, look, fov, static_cast<int>(resolution), 1e-3 * field.box.diagonal());

  const FieldResampler resampler(field);
  const auto t = Clock::now();
  const ResampleResult result = resampler.resample(view, resample);
  const double seconds = seconds_since(t);
  const std::vector<std::uint32_t> faces = resampler.faces_of(result.marked);

  std::optional<Mesh> mesh;
  if (!mesh_path.empty()) {  // checked even without -o: a mismatch is worth knowing
    mesh = read_input(mesh_path, stream);
    check_field_matches(field, *mesh, path, mesh_path);
  }
  if (!out.empty()) {
    std::vector<std::uint8_t> keep(mesh->num_faces(), 0);
    for (std::uint32_t f : faces) keep[f] = 1;
    write_output(keep_faces(*mesh, keep), out, mesh_path, stream, &faces);
  }
  std::ostream& report = out == "-" ? std::cerr : std::cout;
  if (json_out) {
    JsonWriter json(report);
    json.begin_object().field("command", "field query").field("input", path);
    json.key("view").begin_array().value(eye.x).value(eye.y).value(eye.z).end_array();
    json.key("look").begin_array().value(look.x).value(look.y).value(look.z).end_array();
    json.field("fov", fov)
        .field("resolution", resolution)
        .field("subsample", static_cast<std::int64_t>(resample.subsample));
    json.field("interp", interpolation_name(resample.interpolation))
        .field("mip_level", static_cast<std::int64_t>(result.mip_level));
    json.field("cells_marked", result.cells_marked).field("cells_total", field.cells.num_cells());
    json.field("faces_kept", faces.size()).field("faces_total", field.faces);
    json.field("gap_cells", result.gap_cells).field("rays", result.rays).field("rays_in_field", result.rays_in_field);
    json.field("seconds_resample", seconds);
    if (!out.empty()) json.field("output", out);
    json.end_object();
    report << '\n';
  } else if (out.empty()) {
    for (std::size_t c = 0; c < result.marked.size(); ++c) {
      if (result.marked[c]) report << c << '\n';  // one cell id per line: easy to pipe
    }
  } else {
    report << out << ": " << faces.size() << " of " << field.faces << " faces, " << result.cells_marked << " of "
           << field.cells.num_cells() << " cells marked\n";
  }
  return 0;
}

int run_study(const Args& args) {
  FieldStudyOptions options;
  StreamOptions stream;
  std::string dir = "field_study", mode = "object";
  bool groups = false, json_out = false;
  ArgParser parser("visimp field study IN [-o DIR] [options]",
                   "Builds the field of IN with 1 and 5 ids per sample and follows camera paths around and\n"
                   "through the scene: cells and faces drawn, pixels missed against the full render, and the time\n"
                   "of the full render against resampling plus the culled render (raster backend, one thread), for\n"
                   "every post-filter; beside it, visibility tracing (rays at render time) and patch bitfields of\n"
                   "the same cells at equal memory. Writes DIR/study.csv, study.json, SVG plots and index.html.",
                   1, 1);
  parser.add(option_spec("-o", "DIR", dir, "output directory"));
  parser.add(describe_options(options));
  parser.add(option_spec("--cells", "object|polygon|scene", mode,
                         "a grid per object, one cell per face, or one grid over the scene"));
  parser.add(switch_spec("--groups-from-quality", groups, "objects are the faces' quality values"));
  parser.add(switch_spec("--json", json_out, "print study.json to stdout instead of the table"));
  parser.add(option_spec("--format", "FMT", stream.format, "format of '-' (ply, obj, off, stl)"));
  if (!parser.parse(args)) return 0;
  const std::string& in = parser.positionals()[0];
  const Mesh mesh = read_input(in, stream);
  require_faces(mesh, in, "study a visibility field of");
  apply_cell_choice(mode, groups, mesh, in, options.field.cells);
  check_options(options, mesh.num_faces());
  FieldStudy study;
  {
    ProgressBar progress("study");
    study = run_field_study(mesh, options, &progress);
  }
  StagedDirectory staged(dir);
  write_field_study(study, staged.path());
  staged.commit();
  if (json_out) {
    write_field_study_json(study, std::cout);
  } else {
    print_field_study_table(study, std::cout);
    std::cout << "wrote " << dir << "/{study.csv,study.json,index.html,*.svg}\n";
  }
  return 0;
}

}  // namespace

int run_field(const Args& args) {
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    (args.empty() ? std::cerr : std::cout) << kFieldUsage;
    return args.empty() ? 2 : 0;
  }
  const Args rest(args.begin() + 1, args.end());
  if (args[0] == "build") return run_build(rest);
  if (args[0] == "query") return run_query(rest);
  if (args[0] == "study") return run_study(rest);
  throw UsageError("unknown field command '" + args[0] + "' (build, query or study)");
}

}  // namespace visimp::app
