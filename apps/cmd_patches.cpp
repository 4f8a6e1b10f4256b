// visimp patches build / query / study: patch bitfields and view reconstruction from the
// command line (docs/patches.md).
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "backends.h"
#include "cli.h"
#include "commands.h"
#include "visimp/core/content_hash.h"
#include "visimp/core/stopwatch.h"
#include "visimp/core/errors.h"
#include "visimp/core/face_subset.h"
#include "visimp/patches/bitfield_file.h"
#include "visimp/patches/patch_study.h"
#include "visimp/patches/view_reconstruction.h"
#include "visimp/render/image.h"
#include "visimp/report/json.h"
#include "visimp/visibility/visibility.h"

namespace visimp::app {
namespace {

using Clock = std::chrono::steady_clock;

constexpr const char* kPatchesUsage =
    "usage: visimp patches build|query|study ...\n"
    "\n"
    "  build IN [-o OUT.vbf]            patches + one bitfield per camera (Meruvia Pastor)\n"
    "  query FILE.vbf --view X,Y,Z      the patches (or faces) to draw from a viewpoint\n"
    "  study IN [-o DIR]                culling rate, missed pixels and frame times (CSV, JSON, SVG)\n"
    "\n"
    "'visimp patches COMMAND --help' describes each.\n";

int level_of_camera_count(std::size_t count, const std::string& what) {
  for (int level = 0; level <= SphereTessellation::kMaxLevel; ++level) {
    if (octahedron_camera_count(level) == count) return level;
  }
  throw UsageError(what + " must be an octahedron camera count: 6, 18, 66, 258, 1026 or 4098");
}

std::string default_output(const std::string& in) {
  if (in == "-") throw UsageError("reading '-' needs -o OUT.vbf");
  return (std::filesystem::path(in).replace_extension(".vbf")).string();
}

int run_build(const Args& args) {
  SamplingOptions sampling;
  sampling.cameras = "1026";
  PatchOptions patches;
  StreamOptions stream;
  std::string out, transparent_path, patch_ply, patch_png, visibility_out;
  bool per_face = false, neighbour_fill = false, no_compress = false, depth_test = true;
  ArgParser parser("visimp patches build IN [-o OUT.vbf] [--patches N] [--cameras SET] [options]",
                   "Tiles IN into patches (smallest first, fused with the neighbour that keeps the bounding box\n"
                   "smallest), renders it from every camera with each face's ID and records one bit per patch per\n"
                   "camera into OUT.vbf (default: IN with .vbf). --per-face records one bit per face instead\n"
                   "(ID-bitfields). --visibility also computes V(t) from the same frames.",
                   1, 1);
  parser.add(describe_options(sampling));
  parser.add(describe_options(patches));
  parser.add(option_spec("-o", "OUT.vbf", out, "the bitfield file (docs/formats.md)"));
  parser.add(switch_spec("--per-face", per_face, "one bit per face (ID-bitfields) instead of per patch"));
  parser.add(negated_switch_spec("--no-depth-test", depth_test,
                                 "do not set faces that own no pixel but have a vertex at the visible depth"));
  parser.add(switch_spec("--neighbour-fill", neighbour_fill,
                         "also set faces that own no pixel but face the camera next to a face that does"));
  parser.add(option_spec("--transparent-faces", "FILE", transparent_path,
                         "face indices (white space, '#' comments) that are transparent: not rendered, always drawn"));
  parser.add(switch_spec("--no-compress", no_compress, "store rows as plain 64-bit words (default: zero-run coded)"));
  parser.add(option_spec("--patch-ply", "FILE", patch_ply, "write IN with each face's patch number as face quality"));
  parser.add(option_spec("--patch-png", "FILE", patch_png, "write a picture of the patches in distinct colours"));
  parser.add(option_spec("--visibility", "OUT.ply", visibility_out,
                         "also write V(t) as face quality, tallied from the same frames"));
  parser.add(describe_options(stream, false));
  if (!parser.parse(args)) return 0;
  const std::string& in = parser.positionals()[0];
  if (out.empty()) out = default_output(in);
  for (const std::string& written : {out, patch_ply, patch_png, visibility_out}) {
    if (!written.empty() && written == in) throw UsageError(written + " is the input; choose another output name");
  }
  if (!per_face && patches.count == 0 && !(patches.max_diagonal > 0))
    throw UsageError("give --patches N or --max-patch-diagonal D (or --per-face)");
  if (!per_face) check_options(patches);
  if (!visibility_out.empty() && !transparent_path.empty()) {
    throw UsageError("--visibility treats every face as opaque; it cannot be combined with --transparent-faces");
  }
  const CameraSet cameras = camera_set_from_spec(sampling.cameras);
  const auto renderer = make_renderer(sampling.backend, render_options(sampling));

  auto t = Clock::now();
  const Mesh mesh = read_input(in, stream);
  const double read_seconds = seconds_since(t);
  BitfieldOptions options;
  options.neighbour_fill = neighbour_fill;
  options.depth_test = depth_test;
  if (!transparent_path.empty()) options.transparent = read_face_list(transparent_path, mesh.num_faces());

  t = Clock::now();
  const PatchPartition partition = per_face ? faces_as_patches(mesh) : build_patches(mesh, patches);
  const double patch_seconds = seconds_since(t);

  BitfieldSet set = make_bitfield_set(mesh, partition, per_face, cameras, renderer->resolution(), options);

  t = Clock::now();
  std::optional<Visibility> visibility;
  {
    ProgressBar progress("sampling");
    if (visibility_out.empty()) {
      set.bits = record_bitfields(mesh, partition, cameras, *renderer, options, &progress);
    } else {
      // One pass: the tally and the bitfields read the same frames.
      VisibilityOptions job_options;
      job_options.threads = render_options(sampling).threads;  // preparing and finishing, as rendering
      const VisibilityJob job(mesh, renderer->resolution(), job_options);
      BitfieldRecorder recorder(mesh, job.scene(), job.scene_input_faces(), partition, cameras.size(), options);
      const VisibilityTally tally = job.render(cameras, 0, cameras.size(), *renderer, &progress, &recorder);
      set.bits = recorder.finish();
      visibility = job.finish(tally);
    }
  }
  const double sampling_seconds = seconds_since(t);

  t = Clock::now();
  const BitfieldFileSizes sizes = write_bitfield_file(set, out, !no_compress);
  if (!patch_ply.empty()) {
    Mesh tagged = mesh;
    tagged.face_quality.assign(partition.face_patch.begin(), partition.face_patch.end());
    write_output(tagged, patch_ply, in, stream);
  }
  if (!patch_png.empty()) {
    const auto palette = patch_colors(partition.patch_count());
    std::vector<Rgb> colors(mesh.num_faces());
    for (std::size_t f = 0; f < mesh.num_faces(); ++f) colors[f] = palette[partition.face_patch[f]];
    write_png(patch_png, render_face_colors(mesh, colors, kPictureSize));
  }
  if (visibility) {
    Mesh with = mesh;
    with.face_quality = visibility->face;
    with.vertex_quality = visibility->vertex;
    write_output(with, visibility_out, in, stream);
  }
  const double write_seconds = seconds_since(t);

  std::size_t set_bits = 0;
  for (std::size_t c = 0; c < set.bits.cameras; ++c) set_bits += set.bits.count(c);
  const double mean_seen = static_cast<double>(set_bits) / static_cast<double>(cameras.size());
  if (stream.json) {
    JsonWriter json(std::cout);
    json.begin_object()
        .field("command", "patches build")
        .field("input", in)
        .field("input_format", input_format_name(stream))
        .field("format_detected", input_format_detected(stream))
        .field("output", out);
    json.field("faces", mesh.num_faces()).field("unit", per_face ? "face" : "patch");
    json.field("units", partition.patch_count()).field("components", partition.components);
    json.field("camera_set", cameras.name).field("cameras", cameras.size());
    json.field("resolution", static_cast<std::int64_t>(set.resolution)).field("backend", renderer->name());
    json.field("neighbour_fill", neighbour_fill)
        .field("depth_test", depth_test)
        .field("transparent_faces", set.transparent_faces);
    json.field("mean_units_seen_per_camera", mean_seen);
    if (visibility) json.field("mesh_visibility", visibility->mesh);
    json.key("bytes")
        .begin_object()
        .field("total", sizes.total)
        .field("header", sizes.header)
        .field("directions", sizes.directions)
        .field("patch_map", sizes.patch_map)
        .field("bitfields", sizes.bitfields)
        .field("bitfields_uncompressed", sizes.bitfields_uncompressed)
        .end_object();
    json.key("seconds")
        .begin_object()
        .field("read", read_seconds)
        .field("patches", patch_seconds)
        .field("sampling", sampling_seconds)
        .field("write", write_seconds)
        .end_object();
    json.end_object();
    std::cout << '\n';
  } else {
    std::cout << out << ": " << partition.patch_count() << (per_face ? " faces" : " patches") << " x " << cameras.size()
              << " cameras (" << cameras.name << ", " << set.resolution << " px), " << sizes.total
              << " bytes (bitfields " << sizes.bitfields << " of " << sizes.bitfields_uncompressed << " uncompressed)\n"
              << "  mean units seen per camera: " << mean_seen << " of " << partition.patch_count() << "\n"
              << "  seconds: patches " << patch_seconds << ", sampling " << sampling_seconds << "\n";
  }
  return 0;
}

int run_query(const Args& args) {
  std::string view_text, direction_text, mesh_path, out;
  bool faces = false, precompute = false, json_out = false;
  StreamOptions stream;
  ArgParser parser("visimp patches query FILE.vbf (--view X,Y,Z | --direction X,Y,Z) [--faces] [--mesh IN -o OUT]",
                   "Reconstructs the view from a viewpoint on or outside the sampling sphere: ORs the bitfields of\n"
                   "the samples around it and prints the patches (or, with --faces, the faces) to draw, or with\n"
                   "--mesh and -o writes the culled mesh.",
                   1, 1);
  parser.add(option_spec("--view", "X,Y,Z", view_text, "viewpoint in mesh coordinates"));
  parser.add(option_spec("--direction", "X,Y,Z", direction_text, "or: direction from the mesh centre to the viewer"));
  parser.add(switch_spec("--faces", faces, "print face indices instead of patch numbers"));
  parser.add(switch_spec("--precompute", precompute, "join the rows of every cell first (many queries per file)"));
  parser.add(option_spec("--mesh", "IN", mesh_path, "the mesh the file was built from (checked by its hash)"));
  parser.add(option_spec("-o", "OUT", out, "write the culled mesh (needs --mesh; '-' = stdout)"));
  parser.add(switch_spec("--json", json_out, "machine-readable summary"));
  parser.add(option_spec("--format", "FMT", stream.format, "format of '-' (ply, obj, off, stl)"));
  if (!parser.parse(args)) return 0;
  if (view_text.empty() == direction_text.empty()) throw UsageError("give exactly one of --view and --direction");
  if (!out.empty() && mesh_path.empty()) throw UsageError("-o needs --mesh IN: the file holds no geometry");
  const std::string& path = parser.positionals()[0];
  const BitfieldSet set = read_bitfield_file(path);
  const ViewReconstructor reconstructor(set, precompute);
  Vec3 direction;
  bool inside = false;
  if (!view_text.empty()) {
    const Vec3 view = parse_point(view_text, "--view");
    direction = reconstructor.direction_to(view);
    inside = reconstructor.inside_sphere(view);
  } else {
    direction = parse_point(direction_text, "--direction");
    if (!(norm(direction) > 0)) throw UsageError("--direction must not be zero");
  }
  const auto t = Clock::now();
  const std::vector<std::uint32_t> units = reconstructor.units(direction);
  const double query_seconds = seconds_since(t);
  const std::vector<std::uint32_t> drawn = reconstructor.faces(direction);
  const SampleChoice samples = reconstructor.selector().select(direction);
  if (inside)
    std::cerr << "visimp patches query: warning: the viewpoint is inside the sampling sphere; faces may be missed\n";

  if (!out.empty()) {
    const Mesh mesh = read_input(mesh_path, stream);
    check_bitfields_match(set, mesh, path);
    std::vector<std::uint8_t> keep(mesh.num_faces(), 0);
    for (std::uint32_t f : drawn) keep[f] = 1;
    write_output(keep_faces(mesh, keep), out, mesh_path, stream);
  }
  std::ostream& report = out == "-" ? std::cerr : std::cout;
  const double culled =
      1 - static_cast<double>(drawn.size()) / static_cast<double>(std::max<std::uint64_t>(1, set.faces));
  if (json_out) {
    JsonWriter json(report);
    json.begin_object().field("command", "patches query").field("input", path);
    json.field("unit", set.per_face ? "face" : "patch").field("units", set.bits.units).field("faces", set.faces);
    json.key("direction").begin_array().value(direction.x).value(direction.y).value(direction.z).end_array();
    json.field("inside_sampling_sphere", inside);
    json.field("cell", static_cast<std::uint64_t>(reconstructor.selector().cell(direction)));
    json.key("samples").begin_array();
    for (std::size_t i = 0; i < samples.count; ++i) json.value(static_cast<std::uint64_t>(samples.samples[i]));
    json.end_array();
    json.field("units_drawn", units.size()).field("faces_drawn", drawn.size()).field("culling_rate", culled);
    json.field("seconds_query", query_seconds);
    if (out.empty()) {
      json.key(faces ? "draw_faces" : "draw_units").begin_array();
      for (std::uint32_t u : faces ? drawn : units) json.value(static_cast<std::uint64_t>(u));
      json.end_array();
    } else {
      json.field("output", out);
    }
    json.end_object();
    report << '\n';
  } else if (out.empty()) {
    // One index per line: easy to pipe.
    for (std::uint32_t u : faces ? drawn : units) report << u << '\n';
  } else {
    report << out << ": " << drawn.size() << " of " << set.faces << " faces (" << std::setprecision(4) << 100 * culled
           << "% culled) from " << samples.count << " samples\n";
  }
  return 0;
}

int run_study(const Args& args) {
  PatchStudyOptions options;
  SamplingOptions sampling;
  std::string dir = "patch_study", counts_text, timing = "osmesa";
  for (const std::size_t n : options.patch_counts) counts_text += (counts_text.empty() ? "" : ",") + std::to_string(n);
  std::size_t max_cameras = octahedron_camera_count(options.max_level), pixel_cameras = 0;
  bool json_out = false;
  StreamOptions stream;
  ArgParser parser("visimp patches study IN [-o DIR] [--patch-counts N,N,..] [--max-cameras C] [options]",
                   "Samples IN once at the finest camera level and reports, for every patch count and for\n"
                   "per-face ID-bitfields: the culling rate against the number of samples (6 .. C) over random\n"
                   "viewpoints; at one camera level, the pixels that differ between the full mesh and its\n"
                   "reconstruction from random viewpoints and the OSMesa time to draw each. Writes DIR/study.csv,\n"
                   "study.json, culling_vs_samples.svg and culling_vs_patches.svg.",
                   1, 1);
  parser.add(option_spec("-o", "DIR", dir, "output directory"));
  parser.add(option_spec("--patch-counts", "N,N,..", counts_text, "patch counts to compare"));
  parser.add(option_spec("--max-cameras", "C", max_cameras, "finest octahedron set sampled: 6|18|66|258|1026|4098"));
  parser.add(
      option_spec("--pixel-cameras", "C", pixel_cameras, "camera set of the pixel and timing checks (0 = the finest)"));
  parser.add(option_spec("--viewpoints", "N", options.viewpoints, "random viewpoints per culling rate"));
  parser.add(
      option_spec("--pixel-views", "N", options.pixel_views, "random viewpoints rendered full and reconstructed"));
  parser.add(option_spec("--timing-frames", "N", options.timing_frames, "frames timed per viewpoint and mesh"));
  parser.add(option_spec("--timing-backend", "NAME", timing, "osmesa, raster, or none (no frame times)"));
  parser.add(switch_spec("--neighbour-fill", options.neighbour_fill, "fill front-facing neighbours of seen faces"));
  parser.add(negated_switch_spec("--no-depth-test", options.depth_test, "only faces owning a pixel are seen"));
  parser.add(option_spec("--seed", "S", options.seed, "seed of the random viewpoints"));
  std::vector<OptionSpec> render = describe_options(sampling);
  render.erase(render.begin());  // the study picks its own camera sets
  parser.add(render);
  parser.add(switch_spec("--json", json_out, "print study.json to stdout instead of the table"));
  parser.add(option_spec("--format", "FMT", stream.format, "format of '-' (ply, obj, off, stl)"));
  if (!parser.parse(args)) return 0;
  options.patch_counts = parse_count_list(counts_text, "--patch-counts");
  options.max_level = level_of_camera_count(max_cameras, "--max-cameras");
  options.pixel_level = pixel_cameras == 0 ? -1 : level_of_camera_count(pixel_cameras, "--pixel-cameras");
  check_options(options);
  const auto sampler = make_renderer(sampling.backend, render_options(sampling));
  std::unique_ptr<Renderer> timer;
  if (timing != "none") {
    RenderOptions one_thread = render_options(sampling);
    one_thread.threads = 1;  // frame times of one drawing thread, as an interactive viewer has
    timer = make_renderer(timing, one_thread);
  }
  const std::string& in = parser.positionals()[0];
  const Mesh mesh = read_input(in, stream);
  PatchStudy study;
  {
    ProgressBar progress("sampling");
    study = run_patch_study(mesh, *sampler, timer.get(), options, &progress);
  }
  write_patch_study(study, dir);
  if (json_out) {
    write_patch_study_json(study, std::cout);
    return 0;
  }
  std::cout << in << ": " << study.faces << " faces, sampled at " << study.resolution << " px in "
            << study.seconds_sampling << " s; study " << study.seconds_total << " s; files in " << dir << "/\n\n";
  std::cout << "culling rate (mean over " << options.viewpoints << " random viewpoints)\n";
  std::cout << std::setw(26) << "units";
  std::vector<std::size_t> camera_columns;
  for (const CullingPoint& c : study.culling) {
    if (std::find(camera_columns.begin(), camera_columns.end(), c.cameras) == camera_columns.end()) {
      camera_columns.push_back(c.cameras);
      std::cout << std::setw(9) << c.cameras;
    }
  }
  std::cout << '\n';
  for (std::size_t i = 0; i < study.culling.size(); i += camera_columns.size()) {
    const CullingPoint& c = study.culling[i];
    std::cout << std::setw(26) << (c.unit == "faces" ? "faces (ID-bitfields)" : std::to_string(c.patches) + " patches");
    for (std::size_t k = 0; k < camera_columns.size(); ++k) {
      std::cout << std::setw(8) << std::fixed << std::setprecision(1) << 100 * study.culling[i + k].culling_rate << '%';
    }
    std::cout << '\n';
  }
  std::cout << "\nreconstruction from " << options.pixel_views << " random viewpoints\n"
            << std::setw(26) << "units" << std::setw(9) << "cameras" << std::setw(10) << "drawn" << std::setw(12)
            << "diff px" << std::setw(10) << "depth px" << std::setw(10) << "worst" << std::setw(8) << "views"
            << std::setw(12) << "full ms" << std::setw(12) << "culled ms\n";
  for (const PixelCheck& p : study.pixels) {
    std::cout << std::setw(26) << (p.unit == "faces" ? "faces (ID-bitfields)" : std::to_string(p.patches) + " patches")
              << std::setw(9) << p.cameras << std::setw(9) << std::setprecision(1) << 100 * p.drawn_fraction << '%'
              << std::setw(12) << p.differing_pixels << std::setw(10) << p.depth_differing_pixels << std::setw(10)
              << p.max_differing_pixels << std::setw(8) << p.views_with_differences << std::setw(12)
              << std::setprecision(2) << 1000 * p.seconds_per_frame_full << std::setw(11)
              << 1000 * p.seconds_per_frame_culled << '\n';
  }
  return 0;
}

}  // namespace

int run_patches(const Args& args) {
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    (args.empty() ? std::cerr : std::cout) << kPatchesUsage;
    return args.empty() ? 2 : 0;
  }
  const Args rest(args.begin() + 1, args.end());
  if (args[0] == "build") return run_build(rest);
  if (args[0] == "query") return run_query(rest);
  if (args[0] == "study") return run_study(rest);
  throw UsageError("unknown patches command '" + args[0] + "' (build, query or study)");
}

}  // namespace visimp::app
