// The visibility-field study (see field_study.h).
#include "visimp/field/field_study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <map>

#include "visimp/cameras/camera_set.h"
#include "visimp/core/errors.h"
#include "visimp/io/atomic_file.h"
#include "visimp/patches/bitfield_file.h"
#include "visimp/patches/bitfields.h"
#include "visimp/patches/view_reconstruction.h"
#include "visimp/render/perspective.h"
#include "visimp/render/ray_caster.h"
#include "visimp/render/renderer.h"
#include "visimp/report/json.h"
#include "visimp/report/svg_plot.h"

namespace visimp {

std::vector<OptionSpec> describe_options(FieldStudyOptions& o) {
  std::vector<OptionSpec> specs;
  for (OptionSpec& s : describe_options(o.field)) {
    if (s.flag != "--ids") specs.push_back(std::move(s));
  }
  specs.push_back(option_spec("--frames", "N", o.frames, "viewpoints per camera path"));
  specs.push_back(option_spec("--resolution", "R", o.resolution, "image width and height in pixels, 16..8192"));
  specs.push_back(option_spec("--fov", "DEG", o.fov, "field of view across the image, in (0, 170]"));
  specs.push_back(option_spec("--subsample", "K", o.subsample, "resample 1 of K pixels (a square)"));
  return specs;
}

void check_options(const FieldStudyOptions& o, std::size_t faces) {
  check_options(o.field, faces);  // the bound fields themselves, so errors name their flags
  for (const int& ids : o.id_counts) {
    if (ids < 1 || ids > kMaxIds) throw OptionError(&ids, "FieldStudyOptions::id_counts", "must be in [1, 8]");
  }
  if (o.id_counts.empty()) throw OptionError(&o.id_counts, "FieldStudyOptions::id_counts", "must not be empty");
  if (o.frames < 1 || o.frames > 10000)
    throw OptionError(&o.frames, "FieldStudyOptions::frames", "must be in [1, 10000]");
  if (o.resolution < kMinResolution || o.resolution > kMaxResolution)
    throw OptionError(&o.resolution, "FieldStudyOptions::resolution", "must be in [16, 8192]");
  if (!(o.fov > 0 && o.fov <= 170)) throw OptionError(&o.fov, "FieldStudyOptions::fov", "must be in (0, 170]");
  ResampleOptions r;
  r.subsample = o.subsample;
  try {
    check_options(r);
  } catch (const OptionError& e) {
    throw OptionError(&o.subsample, "FieldStudyOptions::subsample", e.problem());
  }
}

VisibilityField truncate_ids(const VisibilityField& field, int ids) {
  VisibilityField out = field;
  out.options.ids = ids;
  const std::size_t from = static_cast<std::size_t>(field.options.ids), to = static_cast<std::size_t>(ids);
  for (auto& slab : out.samples) {
    for (auto& layer : slab) {
      std::vector<std::uint32_t> kept(layer.size() / from * to);
      for (std::size_t s = 0; s < layer.size() / from; ++s) {
        for (std::size_t r = 0; r < to; ++r) kept[s * to + r] = layer[s * from + r];
      }
      layer = std::move(kept);
    }
  }
  return out;
}

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

Vec3 unit_axis(int axis) { return axis == 0 ? Vec3{1, 0, 0} : axis == 1 ? Vec3{0, 1, 0} : Vec3{0, 0, 1}; }

struct Path {
  std::string name;
  std::vector<std::pair<Vec3, Vec3>> views;  // (eye, look), mesh coordinates
};

// "around": an orbit 20° above the plane of the box's two longest axes, at 1.6 half
// diagonals; "through": along the longest axis from outside into the box, looking ahead;
// "front": an arc in front of the +z side (for the single-slab comparison).
std::vector<Path> camera_paths(const BoundingBox& box, std::size_t frames) {
  const Vec3 c = box.center(), h = (box.max - box.min) * 0.5;
  int axes[3] = {0, 1, 2};
  std::sort(axes, axes + 3, [&](int a, int b) { return h[a] > h[b]; });
  const Vec3 eL = unit_axis(axes[0]), eM = unit_axis(axes[1]), eS = unit_axis(axes[2]);
  const double radius = 1.6 * norm(h);
  Path around{"around", {}}, through{"through", {}}, front{"front", {}};
  const double elevation = 20 * M_PI / 180;
  for (std::size_t k = 0; k < frames; ++k) {
    const double theta = 2 * M_PI * static_cast<double>(k) / static_cast<double>(frames);
    const Vec3 eye = c + (eL * std::cos(theta) + eM * std::sin(theta)) * (radius * std::cos(elevation)) +
                     eS * (radius * std::sin(elevation));
    around.views.push_back({eye, c});
    const double f = frames > 1 ? static_cast<double>(k) / static_cast<double>(frames - 1) : 0;
    const double along = -(h[axes[0]] + 0.5 * norm(h)) + f * (1.3 * h[axes[0]] + 0.5 * norm(h));
    const Vec3 p = c + eL * along + eM * (0.25 * h[axes[1]]) + eS * (0.1 * h[axes[2]]);
    through.views.push_back({p, p + eL});
    // Within reach of the paper's single +z slab: 2.5 half diagonals out, ±15° about +z, so
    // every ray to the box is within 45° of −z.
    const double alpha = (f - 0.5) * 30 * M_PI / 180;
    const Vec3 dir{std::sin(alpha), 0.17, std::cos(alpha)};
    front.views.push_back({c + dir * (2.5 * norm(h) / norm(dir)), c});
  }
  return {around, through, front};
}

// Patches for view reconstruction over the field's cells, numbered by lowest face.
PatchPartition cells_as_patches(const Mesh& mesh, const CellPartition& cells) {
  std::vector<std::uint32_t> renumber(cells.num_cells(), 0xffffffffu);
  PatchPartition p;
  p.face_patch.resize(mesh.num_faces());
  std::uint32_t next = 0;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    std::uint32_t& r = renumber[cells.face_cell[f]];
    if (r == 0xffffffffu) r = next++;
    p.face_patch[f] = r;
  }
  p.area.assign(next, 0);
  p.diagonal.assign(next, 0);
  p.face_count.assign(next, 0);
  std::vector<BoundingBox> boxes(next);
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const std::uint32_t q = p.face_patch[f];
    p.area[q] += 0.5 * norm(face_normal_unnormalized(mesh, mesh.faces[f]));
    ++p.face_count[q];
    for (VertexIndex v : mesh.faces[f]) boxes[q].extend(mesh.positions[v]);
  }
  for (std::size_t q = 0; q < next; ++q) p.diagonal[q] = boxes[q].diagonal();
  p.components = cells.objects;
  return p;
}

struct Accumulator {
  FieldStudyRow row;
  std::uint64_t missed = 0, full_pixels = 0;
  void add(double cells, double faces, std::uint64_t missed_px, std::uint64_t full_px, double ms_select,
           double ms_render, double ms_full) {
    ++row.frames;
    row.cells += cells;
    row.faces += faces;
    missed += missed_px;
    full_pixels += full_px;
    row.max_missed_fraction = std::max(row.max_missed_fraction,
                                       full_px ? static_cast<double>(missed_px) / static_cast<double>(full_px) : 0.0);
    row.ms_select += ms_select;
    row.ms_render += ms_render;
    row.ms_full += ms_full;
  }
  FieldStudyRow finish(std::size_t total_cells, std::size_t total_faces) const {
    FieldStudyRow r = row;
    const double n = std::max<double>(1, static_cast<double>(r.frames));
    r.cells /= n;
    r.faces /= n;
    r.ms_select /= n;
    r.ms_render /= n;
    r.ms_full /= n;
    r.cells_fraction = r.cells / static_cast<double>(std::max<std::size_t>(1, total_cells));
    r.faces_fraction = r.faces / static_cast<double>(std::max<std::size_t>(1, total_faces));
    r.missed_fraction = full_pixels ? static_cast<double>(missed) / static_cast<double>(full_pixels) : 0;
    return r;
  }
};

// A pixel is missed when the culled render shows another face at another depth: a hole, or a
// face that should be hidden. Another face at the same depth (a coplanar duplicate winning
// the tie because drawing orders differ) is not a miss. Depths compare as view distances
// (depth = 1 − near/z), relative 1e-4.
std::uint64_t missed_pixels(const PerspectiveFrame& full, const PerspectiveFrame& culled, std::uint64_t& full_pixels) {
  std::uint64_t missed = 0;
  full_pixels = 0;
  for (std::size_t p = 0; p < full.ids.size(); ++p) {
    if (full.ids[p] == 0) continue;
    ++full_pixels;
    if (culled.ids[p] == full.ids[p]) continue;
    const double z_full = 1.0 / (1.0 - full.depth[p]), z_culled = 1.0 / std::max(1e-30, 1.0 - double(culled.depth[p]));
    missed += culled.ids[p] == 0 || std::abs(z_culled - z_full) > 1e-4 * z_full;
  }
  return missed;
}

}  // namespace

FieldStudy run_field_study(const Mesh& mesh, const FieldStudyOptions& options, RenderObserver* observer) {
  const auto start = Clock::now();
  check_options(options, mesh.num_faces());
  FieldStudy study;
  study.faces = mesh.num_faces();
  study.resolution = options.resolution;
  study.uv = options.field.uv;
  study.st = options.field.st;
  study.layers = options.field.layers;
  study.grid = options.field.cells.grid;
  study.cell_mode = cell_mode_name(options.field.cells.mode);
  study.id_counts = options.id_counts;

  // One build with the most ids; fewer ids are a prefix of its ranking.
  FieldOptions build = options.field;
  build.ids = *std::max_element(options.id_counts.begin(), options.id_counts.end());
  const VisibilityField widest = build_field(mesh, build);
  study.seconds_build = widest.seconds_build;
  study.rays = widest.rays;
  study.cells = widest.cells.num_cells();
  study.objects = widest.cells.objects;
  std::vector<VisibilityField> fields;
  for (int ids : options.id_counts) {
    fields.push_back(truncate_ids(widest, ids));
    study.sample_bytes.push_back(fields.back().sample_bytes());
    study.compression_ratio.push_back(measure_field_coding(fields.back()).compression_ratio());
  }
  std::vector<FieldResampler> resamplers;
  resamplers.reserve(fields.size());
  for (const VisibilityField& f : fields) resamplers.emplace_back(f);
  FieldOptions single_options = options.field;
  single_options.ids = options.id_counts.front();
  single_options.slabs = 1;
  single_options.layers = 1;
  const VisibilityField single = build_field(mesh, single_options);
  const FieldResampler single_resampler(single);

  // Geometry for drawing and tracing, relative to the box centre (float precision).
  const BoundingBox& box = widest.box;
  const Vec3 center = box.center();
  std::vector<std::array<float, 3>> relative(mesh.num_vertices());
  for (std::size_t i = 0; i < relative.size(); ++i) {
    const Vec3 p = mesh.positions[i] - center;
    relative[i] = {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
  }
  const RayCaster caster(relative, mesh.faces, static_cast<unsigned>(options.field.threads));

  // (b) patch bitfields over the same cells, as many cameras as the 1-id field's bytes hold.
  std::unique_ptr<ViewReconstructor> reconstructor;
  BitfieldSet patch_set;
  if (options.patches) {
    const PatchPartition partition = cells_as_patches(mesh, widest.cells);
    const std::size_t budget_bits = 8 * study.sample_bytes.front();
    int level = 0;
    while (level < SphereTessellation::kMaxLevel &&
           octahedron_camera_count(level + 1) * partition.patch_count() <= budget_bits)
      ++level;
    const CameraSet cameras = octahedron_cameras(level);
    RenderOptions render;
    render.resolution = options.resolution;
    render.threads = static_cast<unsigned>(options.field.threads);
    const auto renderer = make_raster_renderer(render);
    const BitfieldOptions bit_options;
    patch_set = make_bitfield_set(mesh, partition, false, cameras, options.resolution, bit_options);
    patch_set.bits = record_bitfields(mesh, partition, cameras, *renderer, bit_options);
    study.patch_cameras = cameras.size();
    study.patch_bytes = cameras.size() * ((partition.patch_count() + 63) / 64) * 8;
    reconstructor = std::make_unique<ViewReconstructor>(patch_set, true);
  }

  const std::vector<Path> paths = camera_paths(box, options.frames);
  const Interpolation interps[] = {Interpolation::None, Interpolation::Uv, Interpolation::St, Interpolation::UvSt};
  std::map<std::string, Accumulator> rows;
  std::vector<std::string> order;
  auto accumulator = [&](const std::string& key, const FieldStudyRow& proto) -> Accumulator& {
    auto [it, added] = rows.try_emplace(key);
    if (added) {
      it->second.row = proto;
      order.push_back(key);
    }
    return it->second;
  };

  PerspectiveRasterizer raster;
  PerspectiveFrame full, culled;
  ResampleResult result;
  std::vector<std::uint32_t> faces;
  std::vector<std::uint8_t> marked;
  const double near = 1e-3 * box.diagonal();
  std::size_t done = 0;
  const std::size_t total_frames = paths.size() * options.frames;
  auto draw_culled = [&](const PerspectiveView& view) {
    const auto t = Clock::now();
    raster.draw(relative, mesh.faces, &faces, view, culled);
    return ms_since(t);
  };
  for (const Path& path : paths) {
    study.paths.push_back(path.name);
    std::size_t skipped = 0;
    for (const auto& [eye, look] : path.views) {
      if (observer) observer->on_render_progress(static_cast<double>(done++) / static_cast<double>(total_frames));
      if (widest.inside_solid(eye)) {
        ++skipped;
        continue;
      }
      const PerspectiveView view = PerspectiveView::looking_at(eye, look, options.fov, options.resolution, near);
      PerspectiveView local = view;  // the same view in the drawing frame
      local.eye = eye - center;
      // The full render: best of two (the first warms the caches).
      double ms_full = 1e300;
      for (int k = 0; k < 2; ++k) {
        const auto t = Clock::now();
        raster.draw(relative, mesh.faces, nullptr, local, full);
        ms_full = std::min(ms_full, ms_since(t));
      }
      auto record = [&](Accumulator& acc, double cells, double ms_select, double ms_render) {
        std::uint64_t full_px = 0;
        const std::uint64_t missed = missed_pixels(full, culled, full_px);
        acc.add(cells, static_cast<double>(faces.size()), missed, full_px, ms_select, ms_render, ms_full);
      };
      ResampleOptions resample;
      resample.subsample = options.subsample;
      // "front" only sets six slabs against the paper's one: the first id count, no post-filter.
      const bool front = path.name == "front";
      for (std::size_t i = 0; i < fields.size(); ++i) {
        if (front && i != 0) break;
        for (Interpolation interp : interps) {
          if (front && interp != Interpolation::None) break;
          resample.interpolation = interp;
          const auto t = Clock::now();
          resamplers[i].resample(view, resample, result);
          faces.clear();
          resamplers[i].append_cell_faces(result.marked, faces);
          const double ms_select = ms_since(t);
          const double ms_render = draw_culled(local);
          const std::string key =
              path.name + "/field/" + std::to_string(options.id_counts[i]) + "/" + interpolation_name(interp);
          record(accumulator(key,
                             {path.name, "field", options.id_counts[i], interpolation_name(interp), options.subsample}),
                 static_cast<double>(result.cells_marked), ms_select, ms_render);
        }
      }
      // The paper's single +z slab beside the six (1 id, no post-filter), around and in front.
      if (front || path.name == "around") {
        resample.interpolation = Interpolation::None;
        const auto t = Clock::now();
        single_resampler.resample(view, resample, result);
        faces.clear();
        single_resampler.append_cell_faces(result.marked, faces);
        const double ms_select = ms_since(t);
        const double ms_render = draw_culled(local);
        record(accumulator(path.name + "/single",
                           {path.name, "field, 1 slab", options.id_counts.front(), "none", options.subsample}),
               static_cast<double>(result.cells_marked), ms_select, ms_render);
      }
      if (front) {
        // The 4D mip-map for viewers far from the slabs: the level chosen by distance.
        resample.interpolation = Interpolation::None;
        resample.mip = -1;
        const auto t = Clock::now();
        resamplers.front().resample(view, resample, result);
        faces.clear();
        resamplers.front().append_cell_faces(result.marked, faces);
        const double ms_select = ms_since(t);
        const double ms_render = draw_culled(local);
        record(accumulator(path.name + "/mip",
                           {path.name, "field, mip auto", options.id_counts.front(), "none", options.subsample}),
               static_cast<double>(result.cells_marked), ms_select, ms_render);
        resample.mip = 0;
        continue;
      }
      // (a) visibility tracing: rays at render time through 1 of k pixels.
      for (int k : options.trace_subsamples) {
        const int stride = static_cast<int>(std::lround(std::sqrt(k)));
        const auto t = Clock::now();
        marked.assign(widest.cells.num_cells(), 0);
        const std::array<float, 3> origin{static_cast<float>(local.eye.x), static_cast<float>(local.eye.y),
                                          static_cast<float>(local.eye.z)};
        std::size_t cells = 0;
        for (int j = 0; j * stride < options.resolution; ++j) {
          for (int i = 0; i * stride < options.resolution; ++i) {
            const Vec3 d = view.pixel_ray(i * stride + 0.5 * stride - 0.5, j * stride + 0.5 * stride - 0.5);
            const std::uint32_t f =
                caster.first_hit(origin, {static_cast<float>(d.x), static_cast<float>(d.y), static_cast<float>(d.z)},
                                 static_cast<float>(near));
            if (f != RayCaster::kNoHit) {
              std::uint8_t& m = marked[widest.cells.face_cell[f]];
              cells += m == 0;
              m = 1;
            }
          }
        }
        faces.clear();
        resamplers.front().append_cell_faces(marked, faces);
        const double ms_select = ms_since(t);
        const double ms_render = draw_culled(local);
        record(accumulator(path.name + "/tracing/" + std::to_string(k), {path.name, "tracing", 0, "", k}),
               static_cast<double>(cells), ms_select, ms_render);
      }
      // (b) patch bitfields of the same cells.
      if (reconstructor) {
        const auto t = Clock::now();
        faces = reconstructor->faces(reconstructor->direction_to(eye));
        const double ms_select = ms_since(t);
        std::size_t cells = 0;
        marked.assign(widest.cells.num_cells(), 0);
        for (std::uint32_t f : faces) {
          std::uint8_t& m = marked[widest.cells.face_cell[f]];
          cells += m == 0;
          m = 1;
        }
        const double ms_render = draw_culled(local);
        record(accumulator(path.name + "/patches", {path.name, "patches", 0, "", 0}), static_cast<double>(cells),
               ms_select, ms_render);
      }
    }
    study.frames_skipped.push_back(skipped);
  }
  for (const std::string& key : order) study.rows.push_back(rows[key].finish(study.cells, study.faces));
  if (observer) observer->on_render_progress(1.0);
  study.seconds_total = std::chrono::duration<double>(Clock::now() - start).count();
  return study;
}

namespace {

std::string row_label(const FieldStudyRow& r) {
  if (r.method == "field") return "field, " + std::to_string(r.ids) + " id" + (r.ids > 1 ? "s" : "") + ", " + r.interp;
  if (r.method == "field, 1 slab") return "field, 1 slab (+z)";
  if (r.method == "field, mip auto") return "field, " + std::to_string(r.ids) + " id, mip auto";
  if (r.method == "tracing") return "tracing 1/" + std::to_string(r.subsample);
  return r.method;
}

void write_row_json(JsonWriter& json, const FieldStudyRow& r) {
  json.begin_object().field("path", r.path).field("method", r.method).field("ids", r.ids).field("interp", r.interp);
  json.field("subsample", r.subsample).field("frames", r.frames);
  json.field("cells", r.cells).field("cells_fraction", r.cells_fraction);
  json.field("faces", r.faces).field("faces_fraction", r.faces_fraction);
  json.field("missed_fraction", r.missed_fraction).field("max_missed_fraction", r.max_missed_fraction);
  json.field("ms_select", r.ms_select).field("ms_render", r.ms_render).field("ms_full", r.ms_full);
  json.field("speedup", r.speedup()).end_object();
}

}  // namespace

void write_field_study_json(const FieldStudy& s, std::ostream& out) {
  JsonWriter json(out);
  json.begin_object().field("faces", s.faces).field("cells", s.cells).field("objects", s.objects);
  json.field("cell_mode", s.cell_mode).field("grid", s.grid).field("uv", s.uv).field("st", s.st);
  json.field("layers", s.layers).field("resolution", s.resolution);
  json.field("seconds_build", s.seconds_build).field("rays", s.rays);
  json.key("fields").begin_array();
  for (std::size_t i = 0; i < s.id_counts.size(); ++i) {
    json.begin_object().field("ids", s.id_counts[i]).field("sample_bytes", s.sample_bytes[i]);
    json.field("compression_ratio", s.compression_ratio[i]).end_object();
  }
  json.end_array();
  json.field("patch_cameras", s.patch_cameras).field("patch_bytes", s.patch_bytes);
  json.key("paths").begin_array();
  for (std::size_t i = 0; i < s.paths.size(); ++i) {
    json.begin_object().field("name", s.paths[i]).field("frames_inside_solid", s.frames_skipped[i]).end_object();
  }
  json.end_array();
  json.key("rows").begin_array();
  for (const FieldStudyRow& r : s.rows) write_row_json(json, r);
  json.end_array();
  json.field("seconds_total", s.seconds_total).end_object();
  out << '\n';
}

void print_field_study_table(const FieldStudy& s, std::ostream& out) {
  out << s.faces << " faces, " << s.cells << " cells (" << s.cell_mode << " grid " << s.grid << ", " << s.objects
      << " objects); slabs " << s.uv << "^2 x " << s.st << "^2, " << s.layers << " layers; build "
      << std::setprecision(3) << s.seconds_build << " s\n";
  out << std::left << std::setw(8) << "path" << std::setw(22) << "method" << std::right << std::setw(9) << "cells%"
      << std::setw(9) << "faces%" << std::setw(10) << "missed%" << std::setw(10) << "select" << std::setw(10)
      << "render" << std::setw(10) << "full" << std::setw(9) << "speedup" << '\n';
  auto line = [&](const FieldStudyRow& r) {
    out << std::left << std::setw(8) << r.path << std::setw(22) << row_label(r) << std::right << std::fixed
        << std::setprecision(1) << std::setw(9) << 100 * r.cells_fraction << std::setw(9) << 100 * r.faces_fraction
        << std::setprecision(3) << std::setw(10) << 100 * r.missed_fraction << std::setprecision(2) << std::setw(10)
        << r.ms_select << std::setw(10) << r.ms_render << std::setw(10) << r.ms_full << std::setw(9) << r.speedup()
        << std::defaultfloat << '\n';
  };
  for (const FieldStudyRow& r : s.rows) line(r);
  out << "(times in ms per frame, one thread; missed% = pixels of the full render shown wrong or not at all)\n";
}

void write_field_study(const FieldStudy& s, const std::string& directory) {
  auto write = [&](const std::string& name, const auto& body) {
    AtomicFileWriter file(directory + "/" + name);
    body(file.stream());
    file.commit();
  };
  write("study.json", [&](std::ostream& out) { write_field_study_json(s, out); });
  write("study.csv", [&](std::ostream& out) {
    out << "path,method,ids,interp,subsample,frames,cells,cells_fraction,faces,faces_fraction,missed_fraction,"
           "max_missed_fraction,ms_select,ms_render,ms_full,speedup\n";
    auto line = [&](const FieldStudyRow& r) {
      out << r.path << ',' << r.method << ',' << r.ids << ',' << r.interp << ',' << r.subsample << ',' << r.frames
          << ',' << r.cells << ',' << r.cells_fraction << ',' << r.faces << ',' << r.faces_fraction << ','
          << r.missed_fraction << ',' << r.max_missed_fraction << ',' << r.ms_select << ',' << r.ms_render << ','
          << r.ms_full << ',' << r.speedup() << '\n';
    };
    for (const FieldStudyRow& r : s.rows) line(r);
  });
  // Missed pixels against faces drawn, and frame time against faces drawn, one series per method.
  for (const bool time : {false, true}) {
    SvgPlot plot;
    plot.title = time ? "Frame time against faces drawn" : "Missed pixels against faces drawn";
    plot.subtitle =
        std::to_string(s.faces) + " faces, " + std::to_string(s.cells) + " cells; filled: around, hollow: through";
    plot.x_label = "faces drawn (% of the mesh)";
    plot.y_label = time ? "ms per frame (selection + culled render)" : "missed pixels (% of the full render)";
    std::map<std::string, PlotSeries> series;
    for (const FieldStudyRow& r : s.rows) {
      const std::string label = r.method == "field" ? "field, " + std::to_string(r.ids) + " ids" : row_label(r);
      PlotSeries& ps = series[r.path + ": " + label];
      ps.label = r.path + ": " + label;
      ps.line = r.path == "around" ? LineStyle::solid : LineStyle::dashed;
      ps.points.push_back({100 * r.faces_fraction, time ? r.ms_select + r.ms_render : 100 * r.missed_fraction});
      ps.point_labels.push_back(r.method == "field" ? r.interp : "");
    }
    for (auto& [name, ps] : series) plot.series.push_back(ps);
    if (time) {
      PlotSeries full{"full render", {}, {}};
      for (const FieldStudyRow& r : s.rows) full.points.push_back({100.0, r.ms_full});
      full.points.resize(std::min<std::size_t>(full.points.size(), 1));
      plot.series.push_back(full);
    }
    write(time ? "time.svg" : "missed_vs_faces.svg", [&](std::ostream& out) { plot.write(out); });
  }
  write("index.html", [&](std::ostream& out) {
    out << "<!doctype html><meta charset=utf-8><title>visimp field study</title>\n"
        << "<style>body{font:14px sans-serif;max-width:1000px;margin:2em auto}td,th{padding:2px 8px;text-align:right}"
           "th{background:#eee}td:first-child,td:nth-child(2){text-align:left}</style>\n"
        << "<h1>Visibility field study</h1>\n<p>" << s.faces << " faces in " << s.cells << " cells ("
        << xml_escape(s.cell_mode) << " grid " << s.grid << ", " << s.objects << " objects); six slabs of " << s.uv
        << "&sup2; &times; " << s.st << "&sup2; samples, " << s.layers << " start planes each; built in "
        << short_number(s.seconds_build) << " s (" << s.rays << " rays). Patch bitfields: " << s.patch_cameras
        << " cameras, " << s.patch_bytes << " bytes.</p>\n"
        << "<p><b>Reading the result.</b> <i>missed</i> is the share of the full render's pixels that the culled "
           "render "
           "shows differently (a hole or a face behind it); <i>speedup</i> is the full render's time over selection "
           "plus culled render, on one thread of visimp's rasterizer.</p>\n"
        << "<table><tr><th>path<th>method<th>cells %<th>faces %<th>missed %<th>worst frame %<th>select ms<th>render ms"
           "<th>full ms<th>speedup\n";
    auto line = [&](const FieldStudyRow& r) {
      out << "<tr><td>" << r.path << "<td>" << xml_escape(row_label(r)) << "<td>"
          << short_number(100 * r.cells_fraction) << "<td>" << short_number(100 * r.faces_fraction) << "<td>"
          << short_number(100 * r.missed_fraction) << "<td>" << short_number(100 * r.max_missed_fraction) << "<td>"
          << short_number(r.ms_select) << "<td>" << short_number(r.ms_render) << "<td>" << short_number(r.ms_full)
          << "<td>" << short_number(r.speedup()) << "\n";
    };
    for (const FieldStudyRow& r : s.rows) line(r);
    out << "</table>\n<p><img src=missed_vs_faces.svg><p><img src=time.svg>\n";
  });
}

}  // namespace visimp
