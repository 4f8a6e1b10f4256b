// visimp cells build / walk: walkthrough LODs per navigation cell (docs/cells.md).
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <mutex>
#include <set>

#include "cli.h"
#include "commands.h"
#include "visimp/cells/cell_lod.h"
#include "visimp/cells/cell_store.h"
#include "visimp/cells/walk.h"
#include "visimp/core/errors.h"
#include "visimp/core/parallel.h"
#include "visimp/core/stopwatch.h"
#include "visimp/io/atomic_file.h"
#include "visimp/io/mesh_io.h"
#include "visimp/render/image.h"
#include "visimp/report/json.h"

namespace visimp::app {
namespace {

constexpr const char* kCellsUsage =
    "usage: visimp cells build|walk ...\n"
    "\n"
    "  build SCENE -o DIR [--cell-size C] [--ts PX] [--tl PX]   SVMesh/MVMesh per outside object, per cell\n"
    "  walk SCENE DIR --path PATH|auto [-o OUTDIR]              frames from the cells vs the full scene, PSNR\n"
    "\n"
    "'visimp cells COMMAND --help' describes each.\n";

// The cells a path passes through, and their neighbours (what prefetching reads ahead).
std::vector<HexCell> cells_along(const HexGrid& grid, const std::vector<CameraPose>& path) {
  std::set<std::pair<int, int>> seen;
  std::vector<HexCell> out;
  auto add = [&](const HexCell& c) {
    if (seen.insert({c.r, c.q}).second) out.push_back(c);
  };
  for (const CameraPose& p : path) {
    const HexCell c = grid.cell_of(p.position.x, p.position.y);
    add(c);
    for (const HexCell& n : grid.neighbours(c)) add(n);
  }
  return out;
}

std::vector<CameraPose> path_from(const std::string& text, const Scene& scene, double eye_height, std::size_t frames) {
  if (text == "auto") return auto_camera_path(scene, eye_height, frames);
  return read_camera_path(text);
}

int run_build(const Args& args) {
  CellBuildOptions options;
  std::string out, path_text;
  double cell_size = 50, eye_height = 15;
  std::size_t frames = 400;
  int threads = 0;
  bool json_out = false;
  ArgParser parser(
      "visimp cells build SCENE -o DIR [--cell-size C] [--eye-height H] [--ts PX] [--tl PX] [--resolution R] "
      "[--path PATH|auto] [options]",
      "Tiles the x-y plane of SCENE (a scene JSON, or a mesh whose components are the objects) with\n"
      "hexagonal cells and, per cell, keeps the objects inside it whole (less the faces back-facing to\n"
      "the whole cell) and gives every other object an SVMesh (self-occluding error s <= Ts) or an\n"
      "MVMesh, collapsed with the paper's cost until every edge is longer than Tl pixels of an R x R\n"
      "view. Builds every cell over the scene, or with --path the cells along a walk and their\n"
      "neighbours. Writes DIR/cells.json and one DIR/cell_Q_R.vcell per cell (docs/cells.md).",
      1, 1);
  parser.add(option_spec("-o", "DIR", out, "the cell directory (replaced as a whole)"));
  parser.add(option_spec("--cell-size", "C", cell_size, "hexagon circumradius, scene units"));
  parser.add(option_spec("--eye-height", "H", eye_height, "height of the viewer above z = 0"));
  parser.add(option_spec("--ts", "PX", options.ts_pixels, "self-occluding-error tolerance Ts, pixels"));
  parser.add(option_spec("--tl", "PX", options.tl_pixels, "projected edge-length tolerance Tl, pixels"));
  parser.add(option_spec("--resolution", "R", options.output_resolution, "the walk's image size Ts/Tl refer to"));
  parser.add(option_spec("--fov", "DEG", options.fov_degrees, "the walk's field of view"));
  parser.add(option_spec("--max-capture", "R", options.max_capture_resolution, "cap of depth images and hole tests"));
  parser.add(option_spec("--base-levels", "N", options.base_levels,
                         "quadric versions per mesh to start far objects from (0: the full mesh)"));
  parser.add(negated_switch_spec("--no-textures", options.textures, "no projective textures (geometry only)"));
  parser.add(switch_spec("--cluster", options.clustering, "greedy object clustering (Fig. 5): shared SVMeshes"));
  parser.add(option_spec("--max-cluster", "N", options.max_cluster, "objects a cluster may hold"));
  parser.add(option_spec("--max-texture", "R", options.max_texture_resolution, "largest texture, pixels across"));
  parser.add(option_spec("--path", "PATH|auto", path_text, "build only the cells along this walk (and neighbours)"));
  parser.add(option_spec("--frames", "N", frames, "poses of --path auto"));
  parser.add(option_spec("--threads", "N", threads, "worker threads (0: all cores)"));
  parser.add(switch_spec("--json", json_out, "machine-readable summary"));
  if (!parser.parse(args)) return 0;
  if (out.empty()) throw UsageError("-o DIR is required");
  check_options(options);
  if (threads < 0) throw UsageError("--threads must be >= 0");
  if (frames == 0) throw UsageError("--frames must be >= 1");
  const HexGrid grid(cell_size, eye_height);  // checks both
  const std::string& in = parser.positionals()[0];
  const auto start = std::chrono::steady_clock::now();
  const Scene scene = read_scene(in);
  if (scene.objects.empty()) throw InvalidMeshError(in + ": the scene has no objects");

  std::vector<HexCell> cells;
  if (!path_text.empty()) {
    cells = cells_along(grid, path_from(path_text, scene, eye_height, frames));
  } else {
    BoundingBox box;
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
      const SceneObject& o = scene.objects[i];
      for (const Vec3& p : scene.meshes[o.mesh].positions) box.extend(transform_point(o.transform, p));
    }
    cells = grid.cells_covering(box.min.x, box.min.y, box.max.x, box.max.y);
  }
  if (cells.size() > 100000) throw UsageError("that would be " + std::to_string(cells.size()) + " cells; use a larger --cell-size or --path");

  const auto base_start = std::chrono::steady_clock::now();
  const CellLodBuilder builder(scene, grid, options);
  const double base_seconds = seconds_since(base_start);
  CellManifest manifest;
  manifest.scene_hash = hash_scene(scene);
  manifest.objects = scene.objects.size();
  manifest.cell_size = cell_size;
  manifest.eye_height = eye_height;
  manifest.options = options;
  manifest.cells = cells;
  manifest.cell_faces.assign(cells.size(), 0);
  manifest.cell_seconds.assign(cells.size(), 0);
  std::size_t kinds[4] = {0, 0, 0, 0};
  std::size_t outside_source = 0, outside_lod = 0, outside_original = 0, inside_faces = 0;
  std::mutex stats_mutex;
  StagedDirectory staged(out);
  {
    ProgressBar progress("cells");
    std::atomic<std::size_t> done{0};
    parallel_for(0, cells.size(), worker_count(static_cast<unsigned>(threads), cells.size()),
                 [&](unsigned, std::size_t i) {
                   const auto t = std::chrono::steady_clock::now();
                   const CellLods lods = builder.build(cells[i]);
                   write_cell(lods, manifest.scene_hash, staged.path() + "/" + cell_file_name(cells[i]));
                   std::lock_guard<std::mutex> lock(stats_mutex);
                   manifest.cell_faces[i] = lods.faces();
                   manifest.cell_seconds[i] = seconds_since(t);
                   for (const CellEntry& e : lods.entries) {
                     ++kinds[static_cast<int>(e.kind)];
                     if (e.kind == LodKind::in_cluster) continue;
                     if (e.kind == LodKind::full) {
                       inside_faces += e.faces.size();
                     } else {
                       outside_source += e.source_faces;
                       outside_lod += e.mesh.num_faces();
                       outside_original += scene.meshes[scene.objects[e.object].mesh].num_faces();
                     }
                   }
                   progress.on_progress(static_cast<double>(++done) / static_cast<double>(cells.size()));
                 });
  }
  manifest.seconds = seconds_since(start);
  write_manifest(manifest, staged.path() + "/cells.json");
  staged.commit();

  std::size_t total_faces = 0;
  for (std::size_t f : manifest.cell_faces) total_faces += f;
  const double mean_faces = static_cast<double>(total_faces) / static_cast<double>(cells.size());
  const double ratio = outside_lod ? static_cast<double>(outside_original) / static_cast<double>(outside_lod) : 0;
  if (json_out) {
    JsonWriter json(std::cout);
    json.begin_object().field("command", "cells build").field("input", in).field("output", out);
    json.field("objects", scene.objects.size()).field("scene_faces", scene.face_count());
    json.field("cells", cells.size()).field("cell_size", cell_size).field("eye_height", eye_height);
    json.field("ts", options.ts_pixels).field("tl", options.tl_pixels).field("resolution", options.output_resolution);
    json.key("entries")
        .begin_object()
        .field("full", kinds[0])
        .field("svmesh", kinds[1])
        .field("mvmesh", kinds[2])
        .field("in_cluster", kinds[3])
        .end_object();
    json.field("mean_faces_per_cell", mean_faces).field("inside_faces", inside_faces);
    json.field("outside_original_faces", outside_original).field("outside_source_faces", outside_source);
    json.field("outside_lod_faces", outside_lod).field("original_to_simplified", ratio);
    json.key("seconds").begin_object().field("base_versions", base_seconds).field("total", manifest.seconds).end_object();
    json.end_object();
    std::cout << '\n';
  } else {
    std::cout << out << ": " << cells.size() << " cells of " << scene.objects.size() << " objects ("
              << scene.face_count() << " faces); entries full " << kinds[0] << ", SVMesh " << kinds[1] << ", MVMesh "
              << kinds[2] << "; " << std::fixed << std::setprecision(0) << mean_faces << " faces per cell; outside "
              << "objects simplified 1:" << std::setprecision(1) << ratio << "; " << manifest.seconds << " s\n";
  }
  return 0;
}

// Evicts (cold) or loads (warm) the page cache of every cell file before a walk.
void prepare_cache(const std::string& dir, const CellManifest& manifest, bool cold) {
  for (const HexCell& c : manifest.cells) {
    const std::string path = dir + "/" + cell_file_name(c);
    if (cold) {
      const int fd = ::open(path.c_str(), O_RDONLY);
      if (fd < 0) continue;  // reported when the walk reads it
      ::fdatasync(fd);
      ::posix_fadvise(fd, 0, 0, POSIX_FADV_DONTNEED);
      ::close(fd);
    } else {
      (void)read_file_bytes(path);
    }
  }
}

RgbImage to_rgb(const FrameImage& y) {
  RgbImage out;
  out.width = out.height = y.resolution;
  out.rgb.resize(static_cast<std::size_t>(3) * y.y.size());
  for (int j = 0; j < y.resolution; ++j) {
    for (int i = 0; i < y.resolution; ++i) {
      const std::uint8_t v = y.y[static_cast<std::size_t>(y.resolution - 1 - j) * y.resolution + i];
      for (int c = 0; c < 3; ++c) out.rgb[3 * (static_cast<std::size_t>(j) * y.resolution + i) + c] = v;
    }
  }
  return out;
}

int run_walk(const Args& args) {
  WalkOptions options;
  std::string out, path_text, shading = "smooth", prefetch = "on", cache = "warm", textures = "on";
  std::size_t frames = 400, images = 2;
  bool json_out = false;
  ArgParser parser(
      "visimp cells walk SCENE DIR --path PATH|auto [-o OUTDIR] [--resolution R] [--prefetch on|off] "
      "[--cache cold|warm] [options]",
      "Walks a camera path through SCENE with the cells of DIR (visimp cells build): each frame is drawn\n"
      "from the cell's LOD set (C) and, every --reference-every frames, from the full scene (A) and the\n"
      "full scene frustum-culled per object (B). Reports faces, frame times and PSNR of C against A on\n"
      "luminance. PATH has one 'x y z dx dy dz' pose a line; 'auto' is a loop through the scene.\n"
      "-o writes frames.csv, walk.json and a few frames as PNG (C beside A).",
      2, 2);
  parser.add(option_spec("--path", "PATH|auto", path_text, "the camera path"));
  parser.add(option_spec("--frames", "N", frames, "poses of --path auto"));
  parser.add(option_spec("-o", "OUTDIR", out, "frames.csv, walk.json and PNG frames (replaced as a whole)"));
  parser.add(option_spec("--resolution", "R", options.resolution, "frame size (default: the cells' own)"));
  parser.add(option_spec("--fov", "DEG", options.fov_degrees, "field of view (default: the cells' own)"));
  parser.add(option_spec("--shading", "smooth|flat", shading, "Lambert with interpolated or face normals"));
  parser.add(option_spec("--textures", "on|off", textures, "LOD meshes take their grey from their projective textures"));
  parser.add(option_spec("--prefetch", "on|off", prefetch, "read the neighbouring cells ahead on a low-priority thread"));
  parser.add(option_spec("--cache", "cold|warm", cache, "evict the cell files from the page cache first, or read them"));
  parser.add(option_spec("--reference-every", "K", options.reference_every,
                         "draw A and B (and PSNR) every K-th frame; 0: never (for frame times alone)"));
  parser.add(option_spec("--images", "N", images, "with -o: frames written as PNG (the first and the worst)"));
  parser.add(switch_spec("--json", json_out, "machine-readable summary"));
  if (!parser.parse(args)) return 0;
  if (path_text.empty()) throw UsageError("--path PATH|auto is required");
  if (shading != "smooth" && shading != "flat") throw UsageError("--shading must be smooth or flat");
  if (prefetch != "on" && prefetch != "off") throw UsageError("--prefetch must be on or off");
  if (textures != "on" && textures != "off") throw UsageError("--textures must be on or off");
  if (cache != "cold" && cache != "warm") throw UsageError("--cache must be cold or warm");
  if (frames == 0) throw UsageError("--frames must be >= 1");
  const std::string& in = parser.positionals()[0];
  const std::string& dir = parser.positionals()[1];
  const CellManifest manifest = read_manifest(dir + "/cells.json");
  if (!parser.given("--resolution")) options.resolution = manifest.options.output_resolution;
  if (!parser.given("--fov")) options.fov_degrees = manifest.options.fov_degrees;
  check_pixels(static_cast<std::size_t>(std::max(options.resolution, 0)), "--resolution");
  if (!(options.fov_degrees > 1 && options.fov_degrees < 170)) throw UsageError("--fov must be in (1, 170) degrees");
  options.shading = shading == "flat" ? Shading::flat : Shading::smooth;
  options.prefetch = prefetch == "on";
  options.textures = textures == "on";
  const Scene scene = read_scene(in);
  if (hash_scene(scene) != manifest.scene_hash)
    throw IoError(dir + "/cells.json", "was built for another scene than " + in + " (content hash differs)");
  const std::vector<CameraPose> path = path_from(path_text, scene, manifest.eye_height, frames);
  prepare_cache(dir, manifest, cache == "cold");

  std::vector<FrameImage> first_c, first_a;
  FrameImage worst_c, worst_a;
  double worst_psnr = std::numeric_limits<double>::infinity();
  std::vector<WalkFrame> walked;
  {
    ProgressBar progress("walk");
    walked = walk(scene, dir, manifest, path, options, [&](const WalkFrame& f, const FrameImage& c, const FrameImage& a) {
      progress.on_progress(static_cast<double>(f.index + 1) / static_cast<double>(path.size()));
      if (out.empty() || images == 0 || a.y.empty()) return;
      if (first_c.empty()) {
        first_c.push_back(c);
        first_a.push_back(a);
      }
      if (f.psnr < worst_psnr) {
        worst_psnr = f.psnr;
        worst_c = c;
        worst_a = a;
      }
    });
  }

  // Summary.
  double sum_a = 0, sum_b = 0, sum_c = 0, ms_a = 0, ms_b = 0, ms_c = 0, psnr_sum = 0, psnr_min = INFINITY;
  double cross_ms = 0, cross_max = 0, inner_ms = 0, inner_max = 0;
  std::size_t references = 0, crossings = 0, finite_psnr = 0;
  for (const WalkFrame& f : walked) {
    sum_c += static_cast<double>(f.faces_c);
    ms_c += f.ms_c;
    if (f.crossing && f.index > 0) {
      ++crossings;
      cross_ms += f.ms_c;
      cross_max = std::max(cross_max, f.ms_c);
    } else {
      inner_ms += f.ms_c;
      inner_max = std::max(inner_max, f.ms_c);
    }
    if (!std::isnan(f.psnr)) {
      ++references;
      sum_a += static_cast<double>(f.faces_a);
      sum_b += static_cast<double>(f.faces_b);
      ms_a += f.ms_a;
      ms_b += f.ms_b;
      psnr_min = std::min(psnr_min, f.psnr);
      if (std::isfinite(f.psnr)) {
        psnr_sum += f.psnr;
        ++finite_psnr;
      }
    }
  }
  const double n = static_cast<double>(walked.size()), r = std::max<double>(1, static_cast<double>(references));
  // Frame times of C over the reference frames only, so the ratios compare the same views.
  double ms_c_ref = 0, faces_c_ref = 0;
  for (const WalkFrame& f : walked)
    if (!std::isnan(f.psnr)) {
      ms_c_ref += f.ms_c;
      faces_c_ref += static_cast<double>(f.faces_c);
    }
  const std::size_t inner = walked.size() - crossings;

  auto emit = [&](std::ostream& os) {
    JsonWriter json(os);
    json.begin_object().field("command", "cells walk").field("input", in).field("cells", dir);
    json.field("frames", walked.size()).field("reference_frames", references).field("crossings", crossings);
    json.field("resolution", static_cast<std::int64_t>(options.resolution)).field("shading", shading);
    json.field("prefetch", prefetch).field("cache", cache);
    json.field("textures", textures == "on" && manifest.options.textures);
    json.key("faces")
        .begin_object()
        .field("a", sum_a / r)
        .field("b", sum_b / r)
        .field("c", faces_c_ref / r)
        .field("c_all_frames", sum_c / std::max(1.0, n))
        .end_object();
    json.key("ms")
        .begin_object()
        .field("a", ms_a / r)
        .field("b", ms_b / r)
        .field("c", ms_c_ref / r)
        .field("c_all_frames", ms_c / std::max(1.0, n))
        .field("c_crossing_mean", crossings ? cross_ms / static_cast<double>(crossings) : 0.0)
        .field("c_crossing_max", cross_max)
        .field("c_inside_mean", inner ? inner_ms / static_cast<double>(inner) : 0.0)
        .field("c_inside_max", inner_max)
        .end_object();
    json.key("speedup")
        .begin_object()
        .field("a_over_c", ms_c_ref > 0 ? ms_a / ms_c_ref : 0.0)
        .field("b_over_c", ms_c_ref > 0 ? ms_b / ms_c_ref : 0.0)
        .field("faces_a_over_c", faces_c_ref > 0 ? sum_a / faces_c_ref : 0.0)
        .end_object();
    json.key("psnr")
        .begin_object()
        .field("mean", finite_psnr ? psnr_sum / static_cast<double>(finite_psnr) : INFINITY)
        .field("min", psnr_min)
        .end_object();
    json.end_object();
    os << '\n';
  };
  if (!out.empty()) {
    StagedDirectory staged(out);
    {
      AtomicFileWriter csv(staged.path() + "/frames.csv");
      csv.stream() << "frame,x,y,z,q,r,crossing,faces_a,faces_b,faces_c,ms_a,ms_b,ms_c,read_ms,psnr\n";
      csv.stream() << std::setprecision(6);
      for (const WalkFrame& f : walked) {
        csv.stream() << f.index << ',' << f.pose.position.x << ',' << f.pose.position.y << ',' << f.pose.position.z
                     << ',' << f.cell.q << ',' << f.cell.r << ',' << (f.crossing ? 1 : 0) << ',' << f.faces_a << ','
                     << f.faces_b << ',' << f.faces_c << ',' << f.ms_a << ',' << f.ms_b << ',' << f.ms_c << ','
                     << f.read_ms << ',';
        if (!std::isnan(f.psnr)) csv.stream() << f.psnr;
        csv.stream() << '\n';
      }
      csv.commit();
    }
    if (!first_c.empty()) {
      write_png(staged.path() + "/first_c.png", to_rgb(first_c[0]));
      write_png(staged.path() + "/first_a.png", to_rgb(first_a[0]));
      if (images > 1 && !worst_c.y.empty()) {
        write_png(staged.path() + "/worst_c.png", to_rgb(worst_c));
        write_png(staged.path() + "/worst_a.png", to_rgb(worst_a));
      }
    }
    {
      AtomicFileWriter file(staged.path() + "/walk.json");
      emit(file.stream());
      file.commit();
    }
    staged.commit();
  }
  if (json_out) {
    emit(std::cout);
  } else {
    std::cout << std::fixed << std::setprecision(1) << in << ": " << walked.size() << " frames, " << crossings
              << " cell crossings; faces A " << sum_a / r << ", B " << sum_b / r << ", C " << faces_c_ref / r
              << "; ms A " << ms_a / r << ", B " << ms_b / r << ", C " << ms_c_ref / r << "; PSNR mean "
              << (finite_psnr ? psnr_sum / static_cast<double>(finite_psnr) : INFINITY) << " dB, min " << psnr_min
              << " dB\n";
  }
  return 0;
}

}  // namespace

int run_cells(const Args& args) {
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    (args.empty() ? std::cerr : std::cout) << kCellsUsage;
    return args.empty() ? 2 : 0;
  }
  const Args rest(args.begin() + 1, args.end());
  if (args[0] == "build") return run_build(rest);
  if (args[0] == "walk") return run_walk(rest);
  throw UsageError("unknown cells command '" + args[0] + "' (build or walk)");
}

}  // namespace visimp::app
