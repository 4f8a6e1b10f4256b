// The Python module `visimp` (docs/python.md): numpy arrays in and out, keyword options with
// the library's defaults, the GIL released during every long call and Ctrl-C honoured
// through the library's progress observers. Errors keep their kind: bad input (an array, an
// option, a mesh's content) is ValueError, a file that cannot be read or written OSError.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "arrays.h"
#include "visimp/cameras/camera_set.h"
#include "visimp/compare/compare.h"
#include "visimp/core/bounding_box.h"
#include "visimp/core/errors.h"
#include "visimp/core/option_table.h"
#include "visimp/io/mesh_io.h"
#include "visimp/metrics/image_error.h"
#include "visimp/metrics/surface_distance.h"
#include "visimp/render/osmesa_renderer.h"
#include "visimp/render/renderer.h"
#include "visimp/simplify/simplify.h"
#include "visimp/visibility/visibility.h"

namespace py = pybind11;
using namespace py::literals;

namespace visimp::python {
namespace {

// Thrown out of an observer when Python has a pending signal (KeyboardInterrupt): the
// library unwinds, and the binding re-raises the Python error once it holds the GIL again.
struct Interrupted {};

// Every progress callback the library makes comes from the thread that called it (the one
// that released the GIL), so the pending Python error stays in that thread's state.
class SignalCheck final : public RenderObserver, public SimplifyObserver, public CompareObserver {
 public:
  void on_render_progress(double) override { check(); }
  void on_progress(double) override { check(); }
  void on_compare_progress(const std::string&, double) override { check(); }

 private:
  static void check() {
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) throw Interrupted{};
  }
};

// Runs `work(observer)` without the GIL; a Ctrl-C during it becomes KeyboardInterrupt.
template <class Work>
auto without_gil(Work&& work) {
  SignalCheck signals;
  {
    py::gil_scoped_release release;
    try {
      return work(signals);
    } catch (const Interrupted&) {
    }
  }
  throw py::error_already_set();
}

std::string camera_spec(const py::object& cameras) {
  if (py::isinstance<py::bool_>(cameras)) throw py::value_error("cameras must be a count (6, 18, 66, 258, ...) or a file");
  if (py::isinstance<py::int_>(cameras) || py::isinstance<py::str>(cameras)) return py::str(cameras);
  throw py::value_error("cameras must be a count (6, 18, 66, 258, ...) or a camera file's path");
}

std::unique_ptr<Renderer> make_renderer(const std::string& backend, int resolution, unsigned threads) {
  RenderOptions options;
  options.resolution = resolution;
  options.threads = threads;
  check_render_options(options);
  if (backend == "raster") return make_raster_renderer(options);
  if (backend == "osmesa") return make_osmesa_renderer(options);
  throw py::value_error("backend must be 'raster' or 'osmesa', got '" + backend + "'");
}

struct Sampling {
  CameraSet cameras;
  std::unique_ptr<Renderer> renderer;
};

Sampling sampling(const py::object& cameras, int resolution, unsigned threads, const std::string& backend) {
  Sampling s;
  s.cameras = camera_set_from_spec(camera_spec(cameras));
  s.renderer = make_renderer(backend, resolution, threads);
  return s;
}

py::dict stats_dict(const VisibilityStats& s) {
  return py::dict("input_faces"_a = s.input_faces, "refined_faces"_a = s.refined_faces,
                  "refinement_rounds"_a = s.refinement_rounds, "max_edge_length"_a = s.max_edge_length,
                  "cameras"_a = s.cameras, "resolution"_a = s.resolution, "one_sided_faces"_a = s.one_sided_faces,
                  "two_sided_faces"_a = s.two_sided_faces, "seen_from_behind"_a = s.seen_from_behind,
                  "degenerate_faces"_a = s.degenerate_faces, "unfaced_faces"_a = s.unfaced_faces,
                  "hidden_faces"_a = s.hidden_faces, "hidden_area_fraction"_a = s.hidden_area_fraction,
                  "seconds_prepare"_a = s.seconds_prepare, "seconds_orient"_a = s.seconds_orient,
                  "seconds_refine"_a = s.seconds_refine, "seconds_scene"_a = s.seconds_scene, "seconds_render"_a = s.seconds_render,
                  "seconds_aggregate"_a = s.seconds_aggregate, "seconds"_a = s.seconds_total);
}

py::dict visibility_dict(const Visibility& v) {
  return py::dict("face"_a = floats_to_array(v.face), "face_front"_a = floats_to_array(v.face_front),
                  "face_back"_a = floats_to_array(v.face_back), "vertex"_a = floats_to_array(v.vertex),
                  "mesh"_a = v.mesh, "stats"_a = stats_dict(v.stats));
}

py::dict result_dict(const SimplifyResult& r) {
  return py::dict("faces_in"_a = r.faces_in, "faces_out"_a = r.faces_out, "vertices_in"_a = r.vertices_in,
                  "vertices_out"_a = r.vertices_out, "target_faces"_a = r.target_faces, "collapses"_a = r.collapses,
                  "parallel_collapses"_a = r.parallel_collapses, "rejected_collapses"_a = r.rejected_collapses,
                  "requeued_edges"_a = r.requeued_edges, "locked_vertices"_a = r.locked_vertices,
                  "dropped_faces"_a = r.dropped_faces, "max_error"_a = r.max_error,
                  "stop_reason"_a = to_string(r.stop_reason), "seconds"_a = r.seconds,
                  "stage_seconds"_a = py::dict("setup"_a = r.stage_seconds.setup,
                                               "parallel_phase"_a = r.stage_seconds.parallel_phase,
                                               "serial"_a = r.stage_seconds.serial, "extract"_a = r.stage_seconds.extract));
}

py::tuple simplified_tuple(const Simplified& s) {
  return py::make_tuple(vertices_to_array(s.mesh), faces_to_array(s.mesh), result_dict(s.result));
}

py::dict directed_dict(const DirectedDistance& d, double diagonal) {
  const double scale = diagonal > 0 ? 1 / diagonal : 0;
  return py::dict("max"_a = d.max, "mean"_a = d.mean, "rms"_a = d.rms, "max_relative"_a = d.max * scale,
                  "mean_relative"_a = d.mean * scale, "rms_relative"_a = d.rms * scale, "samples"_a = d.samples,
                  "face_samples"_a = d.face_samples, "area"_a = d.area, "histogram_area_share"_a = doubles_to_array(d.histogram));
}

py::dict distance_dict(const SurfaceDistance& d, bool with_visible) {
  const double scale = d.diagonal > 0 ? 1 / d.diagonal : 0;
  py::dict out("a_to_b"_a = directed_dict(d.a_to_b, d.diagonal), "b_to_a"_a = directed_dict(d.b_to_a, d.diagonal),
               "hausdorff"_a = d.hausdorff, "rms"_a = d.rms, "hausdorff_relative"_a = d.hausdorff * scale,
               "rms_relative"_a = d.rms * scale, "diagonal"_a = d.diagonal, "seconds"_a = d.seconds);
  if (with_visible)
    out["visible"] = py::dict("max"_a = d.visible.max, "mean"_a = d.visible.mean, "rms"_a = d.visible.rms,
                              "visible_area"_a = d.visible.visible_area);
  return out;
}

py::dict image_dict(const ImageError& e) {
  return py::dict("rms"_a = e.rms, "rms_per_pixel"_a = e.rms_per_pixel, "view_rms_per_pixel"_a = doubles_to_array(e.view_rms),
                  "resolution"_a = e.resolution, "supersample"_a = e.supersample, "views"_a = e.views,
                  "seconds"_a = e.seconds);
}

// target: an int face count, or a float in (0, 1] (a fraction of the input's faces).
void set_target(SimplifyOptions& options, const py::object& target) {
  if (target.is_none()) return;
  if (py::isinstance<py::bool_>(target)) throw py::value_error("target must be a face count or a fraction, not a bool");
  if (py::isinstance<py::int_>(target)) {
    const long long faces = target.cast<long long>();
    if (faces < 1) throw py::value_error("target must be at least 1 face, got " + std::to_string(faces));
    options.target_faces = static_cast<std::size_t>(faces);
  } else if (py::isinstance<py::float_>(target)) {
    const double ratio = target.cast<double>();
    if (!(ratio > 0 && ratio <= 1)) throw py::value_error("target as a fraction must be in (0, 1], got " + std::to_string(ratio));
    options.target_ratio = ratio;
  } else {
    throw py::value_error("target must be an int (faces) or a float in (0, 1] (fraction of the faces)");
  }
}

SimplifyMethod parse_method(const std::string& method) {
  if (method == "qb") return SimplifyMethod::qb;
  if (method == "vg") return SimplifyMethod::vg;
  throw py::value_error("method must be 'qb' or 'vg', got '" + method + "'");
}

QuadricWeights parse_quadric_weights(const std::string& weights) {
  if (weights == "uniform") return QuadricWeights::uniform;
  if (weights == "area") return QuadricWeights::area;
  throw py::value_error("quadric_weights must be 'uniform' or 'area', got '" + weights + "'");
}

FaceSampling parse_sampling(const std::string& s) {
  if (s == "random") return FaceSampling::random;
  if (s == "stratified") return FaceSampling::stratified;
  throw py::value_error("sampling must be 'random' or 'stratified', got '" + s + "'");
}

unsigned thread_count(long long threads) {
  if (threads < 0 || threads > static_cast<long long>(kMaxThreads))
    throw py::value_error("threads must be in 0.." + std::to_string(kMaxThreads) + " (0: every core), got " +
                          std::to_string(threads));
  return static_cast<unsigned>(threads);
}

VisibilityOptions visibility_options(bool trust_winding, bool refine, bool depth_test, double depth_tolerance_pixels,
                                     double worst_view_cosine, bool fractional) {
  VisibilityOptions o;
  o.trust_winding = trust_winding;
  o.refine = refine;
  o.depth_test = depth_test;
  o.depth_tolerance_pixels = depth_tolerance_pixels;
  o.worst_view_cosine = worst_view_cosine;
  o.fractional = fractional;
  check_options(o);
  return o;
}

py::object read_mesh_py(const std::string& path, bool face_quality) {
  Mesh mesh = without_gil([&](SignalCheck&) { return read_mesh(path); });
  py::array_t<double> v = vertices_to_array(mesh);
  py::array_t<std::int64_t> f = faces_to_array(mesh);
  if (!face_quality) return py::make_tuple(v, f);
  py::object q = mesh.has_face_quality() ? py::object(floats_to_array(mesh.face_quality)) : py::object(py::none());
  return py::make_tuple(v, f, q);
}

void write_mesh_py(const std::string& path, const py::handle& vertices, const py::handle& faces,
                   const py::object& face_quality, bool binary) {
  Mesh mesh = mesh_from_arrays(vertices, faces, "");
  if (!face_quality.is_none()) mesh.face_quality = face_values_from_array(face_quality, mesh.num_faces(), "face_quality");
  WriteOptions options;
  options.binary = binary;
  without_gil([&](SignalCheck&) {
    write_mesh(mesh, path, std::nullopt, options);
    return 0;
  });
}

py::dict visibility_py(const py::handle& vertices, const py::handle& faces, const py::object& cameras, int resolution,
                       long long threads, const std::string& backend, bool trust_winding, bool refine, bool depth_test,
                       double depth_tolerance_pixels, double worst_view_cosine, bool fractional) {
  const Mesh mesh = mesh_from_arrays(vertices, faces, "");
  VisibilityOptions options =
      visibility_options(trust_winding, refine, depth_test, depth_tolerance_pixels, worst_view_cosine, fractional);
  options.threads = thread_count(threads);
  Sampling s = sampling(cameras, resolution, thread_count(threads), backend);
  const Visibility v = without_gil(
      [&](SignalCheck& signals) { return compute_visibility(mesh, s.cameras, *s.renderer, options, &signals); });
  return visibility_dict(v);
}

py::object simplify_py(const py::handle& vertices, const py::handle& faces, const py::object& target,
                       const std::string& method, const py::object& visibility, const py::object& levels,
                       double max_error, const std::string& quadric_weights, double area_floor, double boundary_weight,
                       bool freeze_boundary, double max_normal_change_deg,
                       bool prevent_folds, double visibility_exponent, bool crease_visibility, bool serial_collapses,
                       const py::object& cameras, int resolution, long long threads, const std::string& backend) {
  const Mesh mesh = mesh_from_arrays(vertices, faces, "");
  SimplifyOptions options;
  set_target(options, target);
  options.method = parse_method(method);
  options.max_error = max_error;
  options.quadric_weights = parse_quadric_weights(quadric_weights);
  options.area_floor = area_floor;
  options.boundary_weight = boundary_weight;
  options.freeze_boundary = freeze_boundary;
  options.max_normal_change_deg = max_normal_change_deg;
  options.prevent_folds = prevent_folds;
  options.visibility_exponent = visibility_exponent;
  options.crease_visibility = crease_visibility;
  options.serial_collapses = serial_collapses;

  std::vector<std::size_t> targets;
  const bool many = !levels.is_none();
  if (many) {
    if (py::isinstance<py::bool_>(levels)) throw py::value_error("levels must be a count or a list of face counts");
    if (py::isinstance<py::int_>(levels)) {
      const long long n = levels.cast<long long>();
      if (n < 1 || n > 1000) throw py::value_error("levels must be in 1..1000, got " + std::to_string(n));
      // The same log-spaced counts as `visimp simplify --levels N` (target, when given, is the lowest).
      const double faces_in = double(std::max<std::size_t>(mesh.num_faces(), 1));
      const double low = options.target_faces > 0 ? double(options.target_faces) / faces_in
                                                   : (options.target_ratio > 0 ? options.target_ratio : CompareOptions{}.min_ratio);
      const double high = CompareOptions{}.max_ratio;
      targets = default_targets(mesh.num_faces(), static_cast<std::size_t>(n), std::min(low, high), high);
    } else {
      for (const py::handle& t : levels) {
        if (py::isinstance<py::bool_>(t) || !py::isinstance<py::int_>(t))
          throw py::value_error("levels must be a count or a list of face counts (ints)");
        const long long faces_at = t.cast<long long>();
        if (faces_at < 1) throw py::value_error("every level must be at least 1 face, got " + std::to_string(faces_at));
        targets.push_back(static_cast<std::size_t>(faces_at));
      }
      if (targets.empty()) throw py::value_error("levels is empty");
    }
  } else {
    check_options(options);
  }

  // VG without V given: measure it first, with the same defaults as `visimp simplify --method vg`.
  std::optional<Sampling> s;
  std::optional<VisibilityOptions> vis_options;
  if (options.method == SimplifyMethod::vg) {
    if (!visibility.is_none()) {
      options.face_visibility = face_values_from_array(visibility, mesh.num_faces(), "visibility");
    } else {
      s = sampling(cameras, resolution, thread_count(threads), backend);
      vis_options = VisibilityOptions{};
      vis_options->threads = thread_count(threads);
    }
  } else if (!visibility.is_none()) {
    throw py::value_error("visibility is only used by method='vg'");
  }

  std::vector<Simplified> results = without_gil([&](SignalCheck& signals) {
    if (s) options.face_visibility = compute_visibility(mesh, s->cameras, *s->renderer, *vis_options, &signals).face;
    std::vector<Simplified> out;
    if (many)
      out = simplify_levels(mesh, options, targets, &signals);
    else
      out.push_back(simplify(mesh, options, &signals));
    return out;
  });
  if (!many) return simplified_tuple(results.front());
  py::list out;
  for (const Simplified& r : results) out.append(simplified_tuple(r));
  return out;
}

SurfaceDistanceOptions metro_options(std::size_t samples, double density, const std::string& sampling_name,
                                     std::uint64_t seed, long long threads, std::size_t edge_samples,
                                     std::size_t histogram_bins) {
  SurfaceDistanceOptions options;
  options.samples = samples;
  options.density = density;
  options.sampling = parse_sampling(sampling_name);
  options.seed = seed;
  options.threads = static_cast<int>(thread_count(threads));
  options.edge_samples = edge_samples;
  options.histogram_bins = histogram_bins;
  if (!(density >= 0) || !std::isfinite(density)) throw py::value_error("density must be >= 0");
  if (histogram_bins < 1) throw py::value_error("histogram_bins must be at least 1");
  return options;
}

py::dict metro_py(const py::handle& a_pair, const py::handle& b_pair, std::size_t samples, double density,
                  const std::string& sampling_name, std::uint64_t seed, long long threads, std::size_t edge_samples,
                  std::size_t histogram_bins, const py::object& visibility) {
  const Mesh a = mesh_from_pair(a_pair, "A"), b = mesh_from_pair(b_pair, "B");
  SurfaceDistanceOptions options =
      metro_options(samples, density, sampling_name, seed, threads, edge_samples, histogram_bins);
  if (!visibility.is_none()) options.face_visibility = face_values_from_array(visibility, a.num_faces(), "visibility");
  const SurfaceDistance d = without_gil([&](SignalCheck&) { return surface_distance(a, b, options); });
  return distance_dict(d, !options.face_visibility.empty());
}

// A measured against many B (the levels of a curve): A's search tree (and samples, while their
// count does not depend on B) are made on the first call and kept. Owns its copy of A, on the
// heap: the library's reference holds A's address.
class MetroReference {
 public:
  MetroReference(const py::handle& a_pair, std::size_t samples, double density, const std::string& sampling_name,
                 std::uint64_t seed, long long threads, std::size_t edge_samples, std::size_t histogram_bins,
                 const py::object& visibility)
      : a_(std::make_unique<Mesh>(mesh_from_pair(a_pair, "A"))),
        options_(metro_options(samples, density, sampling_name, seed, threads, edge_samples, histogram_bins)) {
    if (!visibility.is_none())
      options_.face_visibility = face_values_from_array(visibility, a_->num_faces(), "visibility");
    reference_ = std::make_unique<SurfaceDistanceReference>(*a_);
  }
  py::dict distance_to(const py::handle& b_pair) const {
    const Mesh b = mesh_from_pair(b_pair, "B");
    const SurfaceDistance d = without_gil([&](SignalCheck&) { return reference_->distance_to(b, options_); });
    return distance_dict(d, !options_.face_visibility.empty());
  }

 private:
  std::unique_ptr<Mesh> a_;
  SurfaceDistanceOptions options_;
  std::unique_ptr<SurfaceDistanceReference> reference_;
};

ImageErrorOptions image_options(int resolution, int supersample, long long threads) {
  ImageErrorOptions options;
  options.resolution = resolution;
  options.supersample = supersample;
  options.threads = thread_count(threads);
  return options;
}

py::dict image_error_py(const py::handle& a_pair, const py::handle& b_pair, int resolution, int supersample,
                        long long threads) {
  const Mesh a = mesh_from_pair(a_pair, "A"), b = mesh_from_pair(b_pair, "B");
  const ImageErrorOptions options = image_options(resolution, supersample, threads);
  const ImageError e = without_gil([&](SignalCheck&) { return image_error(a, b, options); });
  return image_dict(e);
}

// A's 20 views drawn once for many B. Owns its copy of A (the library's reference holds A's address).
class ImageReference {
 public:
  ImageReference(const py::handle& a_pair, int resolution, int supersample, long long threads)
      : a_(std::make_unique<Mesh>(mesh_from_pair(a_pair, "A"))) {
    const ImageErrorOptions options = image_options(resolution, supersample, threads);
    reference_ = without_gil([&](SignalCheck&) { return std::make_unique<ImageErrorReference>(*a_, options); });
  }
  py::dict error_to(const py::handle& b_pair) const {
    const Mesh b = mesh_from_pair(b_pair, "B");
    const ImageError e = without_gil([&](SignalCheck&) { return reference_->error_to(b); });
    return image_dict(e);
  }

 private:
  std::unique_ptr<Mesh> a_;
  std::unique_ptr<ImageErrorReference> reference_;
};

py::dict level_dict(const CompareLevel& l) {
  return py::dict("target"_a = l.target, "faces"_a = l.faces, "stop_reason"_a = to_string(l.stop_reason),
                  "seconds_simplify"_a = l.seconds_simplify, "metro"_a = distance_dict(l.distance, true),
                  "image"_a = image_dict(l.image));
}

py::dict compare_py(const std::string& path, const std::string& out_dir, std::size_t levels, const py::object& targets,
                    double min_ratio, double max_ratio, const py::object& cameras, int resolution, long long threads,
                    const std::string& backend, bool visibility_from_quality, std::size_t metro_samples,
                    int image_resolution, std::size_t tie_noise_runs) {
  CompareOptions options;
  options.levels = levels;
  options.min_ratio = min_ratio;
  options.max_ratio = max_ratio;
  if (!targets.is_none()) {
    for (const py::handle& t : targets) {
      if (py::isinstance<py::bool_>(t) || !py::isinstance<py::int_>(t) || t.cast<long long>() < 1)
        throw py::value_error("targets must be face counts (ints >= 1)");
      options.targets.push_back(t.cast<std::size_t>());
    }
  }
  options.visibility_from_quality = visibility_from_quality;
  options.metro_samples = metro_samples;
  options.image.resolution = image_resolution;
  options.image.threads = thread_count(threads);
  options.simplify.threads = options.image.threads;  // every stage on the caller's threads
  options.visibility.threads = options.image.threads;
  options.tie_noise_runs = tie_noise_runs;
  check_options(options);
  Sampling s = sampling(cameras, resolution, thread_count(threads), backend);
  // results.json records what the report was made with, under the app's flag names.
  std::string targets_text, cameras_text = camera_spec(cameras), backend_text = backend;
  for (std::size_t t : options.targets) targets_text += (targets_text.empty() ? "" : ",") + std::to_string(t);
  std::vector<OptionSpec> specs = {option_spec("--targets", "N,N,..", targets_text, "targets")};
  for (OptionSpec& spec : describe_options(options, {option_spec("--cameras", "SET", cameras_text, "cameras"),
                                                     option_spec("--resolution", "R", resolution, "resolution"),
                                                     option_spec("--backend", "NAME", backend_text, "backend")}))
    specs.push_back(std::move(spec));
  auto done = without_gil([&](SignalCheck& signals) {
    const Mesh mesh = read_mesh(path);
    CompareResult result;
    try {
      result = compare_methods(mesh, s.cameras, *s.renderer, options, &signals);
    } catch (const InvalidMeshError& e) {  // name the file: the library does not know it
      throw InvalidMeshError(path + ": " + e.what());
    }
    std::vector<std::string> files = write_compare_report(result, mesh, path, out_dir, specs);
    return std::make_pair(std::move(result), std::move(files));
  });
  const CompareResult& r = done.first;
  py::list qb, vg;
  for (const CompareLevel& l : r.qb) qb.append(level_dict(l));
  for (const CompareLevel& l : r.vg) vg.append(level_dict(l));
  return py::dict("faces_in"_a = r.faces_in, "diagonal"_a = r.diagonal, "mesh_visibility"_a = r.visibility.mesh,
                  "seconds_visibility"_a = r.seconds_visibility, "targets"_a = r.targets, "qb"_a = qb, "vg"_a = vg,
                  "seconds_qb"_a = r.seconds_qb, "seconds_vg"_a = r.seconds_vg,
                  "less_image_error_percent"_a = r.less_image_error_percent,
                  "less_image_error_percent_per_level"_a = r.less_image_error_percent_per_level,
                  "files"_a = done.second);
}

// "SimplifyOptions::max_error must be ..." -> "max_error must be ...": the keyword the caller
// typed (the keywords are the fields' names; the two target fields are the one `target`).
std::string keyword_message(const OptionError& e) {
  const std::string what = e.what();
  const std::size_t scope = what.find("::");
  const std::size_t space = what.find(' ');
  if (scope == std::string::npos || space == std::string::npos || scope > space) return what;
  std::string field = what.substr(scope + 2, space - scope - 2);
  if (field == "target_ratio" || field == "target_faces") field = "target";
  return field + " " + e.problem();
}

}  // namespace
}  // namespace visimp::python

PYBIND11_MODULE(visimp, m) {
  using namespace visimp;
  using namespace visimp::python;
  m.doc() = "visimp: visibility-guided mesh simplification (Zhang & Turk 2002). Meshes are numpy arrays: "
            "V (n, 3) float and F (m, 3) int. Long calls release the GIL and stop on Ctrl-C.";
  m.attr("__version__") = VISIMP_VERSION;

  // IoError is the library's "file could not be read or written": OSError, with the message
  // naming the file. UsageError and InvalidMeshError derive from std::invalid_argument, which
  // pybind11 already turns into ValueError.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const IoError& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    } catch (const OptionError& e) {
      PyErr_SetString(PyExc_ValueError, keyword_message(e).c_str());
    }
  });

  const VisibilityOptions vis{};
  const RenderOptions render{};
  const SimplifyOptions simp{};
  const SurfaceDistanceOptions metro{};
  const ImageErrorOptions image{};
  const CompareOptions cmp{};

  m.def("read_mesh", &read_mesh_py, "path"_a, py::kw_only(), "face_quality"_a = false,
        "Reads PLY, OBJ, OFF or STL (the extension or the content decides). Returns (V, F), or (V, F, Q) "
        "with face_quality=True, Q being the per-face quality (V(t) in a visimp output) or None.");
  m.def("write_mesh", &write_mesh_py, "path"_a, "V"_a, "F"_a, py::kw_only(), "face_quality"_a = py::none(),
        "binary"_a = true,
        "Writes the mesh atomically (a temporary file renamed into place); the format follows the extension. "
        "face_quality (one value in [0, 1] per face) is kept by PLY.");
  m.def("visibility", &visibility_py, "V"_a, "F"_a, py::kw_only(), "cameras"_a = 258, "resolution"_a = render.resolution,
        "threads"_a = 0, "backend"_a = "raster", "trust_winding"_a = vis.trust_winding, "refine"_a = vis.refine,
        "depth_test"_a = vis.depth_test, "depth_tolerance_pixels"_a = vis.depth_tolerance_pixels,
        "worst_view_cosine"_a = vis.worst_view_cosine, "fractional"_a = vis.fractional,
        "Zhang & Turk's visibility V(t) from `cameras` orthographic views (6, 18, 66, 258, 1026, 4098 or a "
        "camera file). Returns a dict: face (V per face), face_front, face_back, vertex, mesh (V(M)), stats.");
  m.def("simplify", &simplify_py, "V"_a, "F"_a, py::kw_only(), "target"_a = py::none(), "method"_a = "qb",
        "visibility"_a = py::none(), "levels"_a = py::none(), "max_error"_a = simp.max_error,
        "quadric_weights"_a = "area", "area_floor"_a = simp.area_floor, "boundary_weight"_a = simp.boundary_weight, "freeze_boundary"_a = simp.freeze_boundary,
        "max_normal_change_deg"_a = simp.max_normal_change_deg, "prevent_folds"_a = simp.prevent_folds,
        "visibility_exponent"_a = simp.visibility_exponent, "crease_visibility"_a = simp.crease_visibility,
        "serial_collapses"_a = simp.serial_collapses, "cameras"_a = 258, "resolution"_a = render.resolution,
        "threads"_a = 0, "backend"_a = "raster",
        "Quadric edge collapse. target: face count (int) or fraction (float in (0, 1]). method 'qb' (plain "
        "quadrics) or 'vg' (visibility-guided; V per face from `visibility`, or measured with cameras/resolution). "
        "Returns (V, F, result); with levels (a list of face counts, or a count of log-spaced levels) a list of them, "
        "all from one collapse sequence (each equals a run to its count with serial_collapses=True).");
  m.def("metro", &metro_py, "A"_a, "B"_a, py::kw_only(), "samples"_a = metro.samples, "density"_a = metro.density,
        "sampling"_a = "random", "seed"_a = metro.seed, "threads"_a = 0, "edge_samples"_a = metro.edge_samples,
        "histogram_bins"_a = metro.histogram_bins, "visibility"_a = py::none(),
        "Metro-style sampled distance between A and B, each a (V, F) pair: one-sided and symmetric Hausdorff, "
        "mean, RMS, histogram; *_relative divide by A's bounding-box diagonal. visibility (V per face of A) "
        "adds the visibility-weighted error.");
  m.def("image_error", &image_error_py, "A"_a, "B"_a, py::kw_only(), "resolution"_a = image.resolution,
        "supersample"_a = image.supersample, "threads"_a = 0,
        "Image RMS error (eq. 5.11) from the 20 dodecahedron views of A's bounding sphere, flat-shaded.");
  py::class_<MetroReference>(m, "MetroReference",
                             "A kept for measuring many B against it (the levels of a curve): A's search tree is "
                             "made once, and A's samples while their count does not depend on B. distance_to(B) "
                             "equals metro(A, B) with the same options.")
      .def(py::init<const py::handle&, std::size_t, double, const std::string&, std::uint64_t, long long,
                    std::size_t, std::size_t, const py::object&>(),
           "A"_a, py::kw_only(), "samples"_a = metro.samples, "density"_a = metro.density, "sampling"_a = "random",
           "seed"_a = metro.seed, "threads"_a = 0, "edge_samples"_a = metro.edge_samples,
           "histogram_bins"_a = metro.histogram_bins, "visibility"_a = py::none())
      .def("distance_to", &MetroReference::distance_to, "B"_a, "metro(A, B): the same dict, A's share made once.");
  py::class_<ImageReference>(m, "ImageErrorReference",
                             "A's 20 views drawn once for many B. error_to(B) equals image_error(A, B) with the "
                             "same options.")
      .def(py::init<const py::handle&, int, int, long long>(), "A"_a, py::kw_only(),
           "resolution"_a = image.resolution, "supersample"_a = image.supersample, "threads"_a = 0)
      .def("error_to", &ImageReference::error_to, "B"_a, "image_error(A, B): the same dict, A drawn once.");
  m.def("compare", &compare_py, "path"_a, "out_dir"_a, py::kw_only(), "levels"_a = cmp.levels,
        "targets"_a = py::none(), "min_ratio"_a = cmp.min_ratio, "max_ratio"_a = cmp.max_ratio, "cameras"_a = 258,
        "resolution"_a = render.resolution, "threads"_a = 0, "backend"_a = "raster",
        "visibility_from_quality"_a = cmp.visibility_from_quality, "metro_samples"_a = cmp.metro_samples,
        "image_resolution"_a = cmp.image.resolution, "tie_noise_runs"_a = cmp.tie_noise_runs,
        "QB against VG at several face counts, as `visimp compare`: writes the report into out_dir and returns "
        "its numbers as a dict (per level and method: faces, seconds, metro, image).");
}
