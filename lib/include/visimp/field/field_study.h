// The visibility-field study (Blais & Poulin Figs. 8–11 and §6, on our meshes): along camera
// paths around and through the scene, per post-filter and ids per sample, the cells and
// faces drawn, the pixels missed against the full render (the metric the paper asks for in
// §8), and the frame time of the full render against resampling plus the culled render
// (visimp's CPU rasterizer, one thread). On the same viewpoints, for comparison:
//   (a) visibility tracing: rays from the eye at render time through 1 of k pixels (Embree);
//   (b) patch bitfields (`visimp patches`) over the same cells, with as many cameras as fit
//       in the memory of the 1-id field.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "visimp/core/mesh.h"
#include "visimp/field/field.h"
#include "visimp/field/resample.h"

namespace visimp {

struct FieldStudyOptions {
  FieldStudyOptions() { field.layers = 4; }  // the "through" path goes inside the box
  FieldOptions field;                        ///< ids are the study's id_counts
  std::vector<int> id_counts{1, 5};
  int resolution = 480;
  double fov = 60;
  int subsample = 4;
  std::size_t frames = 16;                    ///< per path
  std::vector<int> trace_subsamples{4, 100};  ///< visibility tracing: 1 of k pixels
  bool patches = true;                        ///< (b)
};

/// --frames, --resolution, --fov, --subsample and the field's options except --ids.
std::vector<OptionSpec> describe_options(FieldStudyOptions& options);
void check_options(const FieldStudyOptions& options, std::size_t faces);

/// One method on one path, averaged over the path's frames.
struct FieldStudyRow {
  std::string path;    ///< "around", "through", "front"
  /// "field", "field, 1 slab" (the paper's single +z slab, on "around" and "front"),
  /// "field, mip auto" (the 4D mip-map, on "front"), "tracing", "patches"
  std::string method;
  int ids = 0;         ///< field: ids per sample
  std::string interp;  ///< field: post-filter
  int subsample = 0;   ///< field and tracing: 1 of k pixels
  std::size_t frames = 0;
  double cells = 0, cells_fraction = 0;  ///< marked, mean
  double faces = 0, faces_fraction = 0;  ///< drawn, mean
  double missed_fraction = 0;            ///< missed pixels / pixels of the full render, over the path
  double max_missed_fraction = 0;        ///< in the worst frame
  double ms_select = 0, ms_render = 0;   ///< resampling (or tracing, or joining bitfields) and culled drawing
  double ms_full = 0;                    ///< the full render on the same frames
  double speedup() const { return ms_select + ms_render > 0 ? ms_full / (ms_select + ms_render) : 0; }
};

struct FieldStudy {
  std::size_t faces = 0, cells = 0, objects = 0;
  int resolution = 0, uv = 0, st = 0, layers = 0, grid = 0;
  std::string cell_mode;
  double seconds_build = 0;  ///< the field with the most ids (fewer ids are its prefix)
  std::uint64_t rays = 0;
  std::vector<int> id_counts;
  std::vector<std::size_t> sample_bytes;  ///< per id count, at the stored id width
  std::vector<double> compression_ratio;  ///< per id count, run-length coding
  std::size_t patch_cameras = 0, patch_bytes = 0;
  std::vector<std::string> paths;
  std::vector<std::size_t> frames_skipped;  ///< per path: viewpoints inside solid geometry
  std::vector<FieldStudyRow> rows;
  double seconds_total = 0;
};

class RenderObserver;
FieldStudy run_field_study(const Mesh& mesh, const FieldStudyOptions& options, RenderObserver* observer = nullptr);

/// study.csv, study.json, missed_vs_faces.svg, time.svg and index.html in `directory`.
void write_field_study(const FieldStudy& study, const std::string& directory);
void write_field_study_json(const FieldStudy& study, std::ostream& out);
void print_field_study_table(const FieldStudy& study, std::ostream& out);

/// A field with the same samples keeping only the first `ids` of each (ranking is a prefix).
VisibilityField truncate_ids(const VisibilityField& field, int ids);

}  // namespace visimp
