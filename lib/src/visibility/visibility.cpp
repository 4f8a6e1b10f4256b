// The visibility measure (see visibility.h; Zhang & Turk 2002, eqs. 3.2 and 4.3).
//
// Per camera, on the worker that rendered the frame:
//   1. every pixel marks the face it shows as seen (binary F: the frame's number in
//      `seen_in_frame`, so nothing needs clearing; fractional F: a pixel count in `owned`);
//   2. depth test: a vertex counts as visible when it is not behind the depth buffer by more
//      than the tolerance at one of the four pixel centres around it;
//   3. one pass over the faces adds q(R·N) to `total` for every face turned toward the
//      camera and to `seen` when the face owns a pixel or one of its vertices is visible;
//   4. (fractional F only) the counts are cleared through the same pixels.
// Workers add integers into their own arrays, summed at the end: any thread count gives
// the same bits.
#include "visimp/visibility/visibility.h"
#include "visimp/core/stopwatch.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "visimp/core/bounding_box.h"
#include "visimp/core/content_hash.h"
#include "visimp/core/face_subset.h"
#include "visimp/core/spatial_order.h"
#include "visimp/core/errors.h"
#include "visimp/core/mesh_stats.h"
#include "visimp/core/union_find.h"

namespace visimp {
namespace {



std::uint64_t hash_cameras(const CameraSet& cameras) { return hash_directions(cameras.directions); }

std::array<float, 3> to_float(const Vec3& v) {
  return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
}

float dot(const std::array<float, 3>& a, const std::array<float, 3>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

struct FaceTally {
  std::uint32_t seen = 0, total = 0;  // together: one cache line serves both
};

// Per-worker accumulators; see the file comment for the four steps.
class TallyConsumer final : public FrameConsumer {
  struct Worker {
    std::vector<FaceTally> tally;
    std::vector<std::uint16_t> owned;  // fractional F: pixels owned in the current frame (saturating)
    std::vector<std::uint32_t> seen_in_frame;  // binary F: number of the last frame the face owned a pixel in
    std::uint32_t frame_number = 0;
    std::vector<float> depth_gap;      // per vertex: how far behind the depth buffer it is
  };
 public:
  TallyConsumer(const RenderScene& scene, const std::vector<std::array<float, 3>>& face_normals,
                const VisibilityOptions& options)
      : scene_(scene), face_normals_(face_normals), options_(options) {}

  void begin(unsigned workers) override { workers_.resize(workers); }

  void consume(const Frame& frame, std::size_t, unsigned worker) override {
    Worker& w = workers_[worker];
    const std::size_t faces = scene_.faces.size();
    if (w.tally.empty()) {
      w.tally.resize(faces);
      if (options_.fractional) w.owned.assign(faces, 0);
      w.seen_in_frame.assign(faces, 0);
      w.depth_gap.assign(scene_.positions.size(), 0.0f);
    }
    const std::array<float, 3> direction = to_float(frame.view.direction);
    const std::uint32_t* ids = frame.ids.data();
    const std::size_t pixels = frame.ids.size();
    const std::uint32_t frame_number = ++w.frame_number;
    if (options_.fractional) {
      for (std::size_t p = 0; p < pixels; ++p) {
        if (ids[p] != 0 && w.owned[ids[p] - 1] != 0xffffu) ++w.owned[ids[p] - 1];
      }
    } else {
      std::uint32_t* seen = w.seen_in_frame.data();
      for (std::size_t p = 0; p < pixels; ++p) {
        if (ids[p] != 0) seen[ids[p] - 1] = frame_number;
      }
    }
    if (options_.depth_test) measure_depth_gaps(frame, w.depth_gap);
    const std::array<float, 256> tolerance = tolerance_by_weight(frame.resolution());

    for (std::size_t first = 0; first < faces; first += RenderScene::kClusterSize) {
      // No face of such a cluster has weight for this camera.
      if (scene_.clusters[first / RenderScene::kClusterSize].all_back_facing(direction)) continue;
      const std::size_t last = std::min(faces, first + RenderScene::kClusterSize);
      if (options_.fractional) {
        for (std::size_t t = first; t < last; ++t) add_fractional(t, direction, frame, tolerance, w);
        continue;
      }
      // Binary F without data-dependent branches: a face with q = 0 adds nothing anyway.
      for (std::size_t t = first; t < last; ++t) {
        const std::uint32_t q = quantize_weight(dot(face_normals_[t], direction));
        FaceTally& tally = w.tally[t];
        tally.total += q;
        bool visible = w.seen_in_frame[t] == frame_number;
        if (options_.depth_test) {
          const Face& f = scene_.faces[t];
          const float gap = std::min({w.depth_gap[f[0]], w.depth_gap[f[1]], w.depth_gap[f[2]]});
          visible |= gap <= tolerance[q >> 8];
        }
        tally.seen += visible ? q : 0u;
      }
    }
    if (options_.fractional) {
      for (std::size_t p = 0; p < pixels; ++p) {
        if (ids[p] != 0) w.owned[ids[p] - 1] = 0;
      }
    }
  }

  // F = the fraction of the projected area that owns pixels; a face smaller than a pixel
  // that is seen at all counts as wholly seen.
  void add_fractional(std::size_t t, const std::array<float, 3>& direction, const Frame& frame,
                      const std::array<float, 256>& tolerance, Worker& w) const {
    const std::uint32_t q = quantize_weight(dot(face_normals_[t], direction));
    if (q == 0) return;
    FaceTally& tally = w.tally[t];
    tally.total += q;
    const Face& f = scene_.faces[t];
    const std::uint32_t owned = w.owned[t];
    if (owned == 0) {
      const float gap = std::min({w.depth_gap[f[0]], w.depth_gap[f[1]], w.depth_gap[f[2]]});
      if (!options_.depth_test || gap > tolerance[q >> 8]) return;
    }
    const ScreenVertex &a = frame.vertices[f[0]], &b = frame.vertices[f[1]], &c = frame.vertices[f[2]];
    const float area = 0.5f * std::abs((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
    const float fraction = std::min(1.0f, std::max(static_cast<float>(owned), 1.0f) / std::max(area, 1.0f));
    tally.seen += static_cast<std::uint32_t>(static_cast<float>(q) * fraction + 0.5f);
  }

  /// Sum of all workers' tallies.
  void add_to(VisibilityTally& out) const {
    for (const Worker& w : workers_) {
      for (std::size_t t = 0; t < w.tally.size(); ++t) {
        out.seen[t] += w.tally[t].seen;
        out.total[t] += w.tally[t].total;
      }
    }
  }

 private:


  // How far each vertex lies behind the farthest of the depth buffer's values at the four
  // pixel centres around it (negative: in front). A vertex of the visible surface is at
  // most slope × 0.71 px behind the nearest of those centres.
  static void measure_depth_gaps(const Frame& frame, std::vector<float>& gap) {
    const int size = frame.resolution();
    const auto row = static_cast<std::size_t>(size);
    const float* depth = frame.depth.data();
    for (std::size_t i = 0; i < frame.vertices.size(); ++i) {
      const ScreenVertex& v = frame.vertices[i];
      // Screen coordinates are positive, so truncation is the floor (or 0 where clamped anyway).
      const int px = std::min(static_cast<int>(v.x - 0.5f), size - 2);
      const int py = std::min(static_cast<int>(v.y - 0.5f), size - 2);
      const std::size_t p = static_cast<std::size_t>(py) * row + static_cast<std::size_t>(px);
      gap[i] = v.depth - std::max({depth[p], depth[p + 1], depth[p + row], depth[p + row + 1]});
    }
  }

  // Depth tolerance of a face by its quantised weight q (= cos θ · 65535, binned by q >> 8):
  // the base tolerance plus the depth change of the face's own plane over 0.71 px, with
  // the slope capped at the worst viewing angle. The bin's lower edge is used, so the
  // tolerance is never too small.
  std::array<float, 256> tolerance_by_weight(int resolution) const {
    std::array<float, 256> table;
    const double pixel_depth = 1.0 / resolution;  // one pixel, in depth units
    for (int b = 0; b < 256; ++b) {
      const double c = std::max(b / 256.0, options_.worst_view_cosine);
      const double tangent = std::sqrt(1.0 - c * c) / c;
      table[static_cast<std::size_t>(b)] =
          static_cast<float>((options_.depth_tolerance_pixels + 0.7072 * tangent) * pixel_depth);
    }
    return table;
  }

  const RenderScene& scene_;
  const std::vector<std::array<float, 3>>& face_normals_;
  const VisibilityOptions& options_;
  std::vector<Worker> workers_;
};

}  // namespace

std::vector<OptionSpec> describe_options(VisibilityOptions& o) {
  return {
      option_spec("--worst-view-cosine", "C", o.worst_view_cosine,
                  "cosine of the worst viewing angle; edges longer than pixel/C are split, (0, 1]"),
      negated_switch_spec("--no-refine", o.refine, "do not split long edges (to study the effect)"),
      negated_switch_spec("--no-depth-test", o.depth_test, "only pixel ownership decides F (to study the effect)"),
      option_spec("--depth-tolerance", "PX", o.depth_tolerance_pixels,
                  "depth-test tolerance in pixels, added to the slope allowance, [0, 16]"),
      switch_spec("--fractional", o.fractional, "F = visible fraction of the projected area instead of 0/1"),
      option_spec("--max-refined-faces", "N", o.max_refined_faces, "refuse to refine beyond N faces"),
  };
}

void check_options(const VisibilityOptions& o) {
  if (!(o.worst_view_cosine > 0 && o.worst_view_cosine <= 1)) throw UsageError("--worst-view-cosine must be in (0, 1]");
  if (!(o.depth_tolerance_pixels >= 0 && o.depth_tolerance_pixels <= 16))
    throw UsageError("--depth-tolerance must be in [0, 16] pixels");
  if (o.max_refined_faces == 0) throw UsageError("--max-refined-faces must be positive");
}

bool back_faces_always_hidden(const Mesh& mesh) {
  const MeshStats stats = analyze(mesh);
  if (!stats.closed_manifold() || stats.misoriented_edges != 0 || stats.degenerate_faces != 0) return false;
  // Every component must enclose positive volume (outward normals), or a ray from outside
  // could meet a back face first.
  UnionFind components(mesh.positions.size());
  for (const Face& f : mesh.faces) {
    components.unite(f[0], f[1]);
    components.unite(f[0], f[2]);
  }
  std::vector<double> volume(mesh.positions.size(), 0.0);
  const Vec3 center = stats.bbox.center();
  for (const Face& f : mesh.faces) {
    const Vec3 a = mesh.positions[f[0]] - center, b = mesh.positions[f[1]] - center, c = mesh.positions[f[2]] - center;
    volume[components.find(f[0])] += dot(a, cross(b, c));
  }
  for (std::uint32_t v = 0; v < volume.size(); ++v) {
    if (components.find(v) == v && volume[v] < 0) return false;
  }
  return true;
}

VisibilityJob::VisibilityJob(const Mesh& mesh, int resolution, const VisibilityOptions& options)
    : input_(mesh), options_(options), resolution_(resolution) {
  const auto start = std::chrono::steady_clock::now();
  check_options(options);
  check_render_options({resolution, 0});
  stats_.input_faces = mesh.num_faces();
  stats_.resolution = resolution;
  for (const Face& f : mesh.faces) stats_.degenerate_faces += is_degenerate(mesh, f) ? 1 : 0;

  const bool cull = back_faces_always_hidden(mesh);
  const BoundingBox box = bounding_box(mesh);
  const double radius = view_radius(box);
  stats_.max_edge_length = refinement_edge_length(radius, resolution, options.worst_view_cosine);
  if (options.refine) refined_ = refine_long_edges(mesh, stats_.max_edge_length, options.max_refined_faces);
  stats_.refinement_rounds = refined_ ? refined_->rounds : 0;
  const Mesh& rendered = rendered_mesh();
  stats_.refined_faces = rendered.num_faces();
  stats_.back_faces_culled = cull;
  // The scene holds the faces in spatial order and the vertices in order of first use.
  scene_order_ = spatial_face_order(rendered);
  const Vec3 center = bounding_box(rendered).center();
  scene_.radius = radius;
  scene_.cull_back_faces = cull;
  scene_.faces.resize(rendered.num_faces());
  unit_normals_.resize(rendered.num_faces());
  constexpr VertexIndex kUnused = 0xffffffffu;
  std::vector<VertexIndex> scene_vertex(rendered.num_vertices(), kUnused);
  for (std::size_t t = 0; t < scene_order_.size(); ++t) {
    const Face& f = rendered.faces[scene_order_[t]];
    const Vec3 n = face_normal_unnormalized(rendered, f);
    const bool degenerate = is_degenerate(rendered, f);
    unit_normals_[t] = degenerate ? std::array<float, 3>{0, 0, 0} : to_float(n / norm(n));
    for (int k = 0; k < 3; ++k) {
      VertexIndex& v = scene_vertex[f[k]];
      if (v == kUnused) {
        v = static_cast<VertexIndex>(scene_.positions.size());
        scene_.positions.push_back(to_float(rendered.positions[f[k]] - center));
      }
      scene_.faces[t][k] = v;
    }
  }
  scene_.compute_normal_cones(unit_normals_);
  mesh_hash_ = hash_mesh(mesh);
  stats_.seconds_refine = seconds_since(start);
}

TallyKey VisibilityJob::key(const CameraSet& cameras) const {
  TallyKey key;
  key.mesh_hash = mesh_hash_;
  key.camera_hash = hash_cameras(cameras);
  key.camera_count = cameras.size();
  key.faces = scene_.faces.size();
  key.resolution = static_cast<std::uint32_t>(resolution_);
  key.flags = (options_.fractional ? TallyKey::kFractional : 0) | (options_.depth_test ? TallyKey::kDepthTest : 0) |
              (options_.refine ? 0 : TallyKey::kNoRefine);
  key.worst_view_cosine = options_.worst_view_cosine;
  key.depth_tolerance_pixels = options_.depth_tolerance_pixels;
  return key;
}

VisibilityTally VisibilityJob::render(const CameraSet& cameras, std::size_t first, std::size_t last,
                                      Renderer& renderer, RenderObserver* observer, FrameConsumer* also) const {
  if (cameras.size() == 0 || cameras.size() > VisibilityTally::kMaxCameras) {
    throw UsageError("a camera set needs 1..65536 cameras, got " + std::to_string(cameras.size()));
  }
  if (first > last || last > cameras.size()) {
    throw UsageError("camera range " + std::to_string(first) + ":" + std::to_string(last) + " is outside 0:" +
                     std::to_string(cameras.size()));
  }
  if (renderer.resolution() != resolution_) {
    throw UsageError("renderer resolution " + std::to_string(renderer.resolution()) +
                     " differs from the job's " + std::to_string(resolution_));
  }
  VisibilityTally tally;
  tally.key = key(cameras);
  if (first < last) tally.camera_ranges.emplace_back(first, last);
  tally.seen.assign(scene_.faces.size(), 0);
  tally.total.assign(scene_.faces.size(), 0);
  TallyConsumer consumer(scene_, unit_normals_, options_);
  if (also != nullptr) {
    FrameFanOut both({&consumer, also});
    renderer.render(scene_, cameras, first, last, both, observer);
  } else {
    renderer.render(scene_, cameras, first, last, consumer, observer);
  }
  consumer.add_to(tally);
  return tally;
}

std::vector<std::uint32_t> VisibilityJob::scene_input_faces() const {
  std::vector<std::uint32_t> input(scene_order_.size());
  for (std::size_t t = 0; t < scene_order_.size(); ++t) {
    input[t] = refined_ ? refined_->input_face[scene_order_[t]] : scene_order_[t];
  }
  return input;
}

Visibility VisibilityJob::finish(const VisibilityTally& tally) const {
  const auto start = std::chrono::steady_clock::now();
  if (tally.key.faces != scene_.faces.size() || tally.key.mesh_hash != mesh_hash_ ||
      tally.key.resolution != static_cast<std::uint32_t>(resolution_)) {
    throw UsageError("the tally was made for a different mesh, resolution or refinement");
  }
  if (!tally.complete()) {
    throw UsageError("cameras " + tally.describe_missing() + " of " + std::to_string(tally.key.camera_count) +
                     " are missing from the tally; merge their slices first");
  }
  Visibility out;
  out.stats = stats_;
  out.stats.cameras = tally.key.camera_count;
  const Mesh& rendered = rendered_mesh();
  const std::size_t input_faces = input_.num_faces();

  // Input face V = area-weighted mean over its sub-faces that some camera faced.
  std::vector<double> weighted(input_faces, 0.0), weight(input_faces, 0.0);
  for (std::size_t t = 0; t < scene_order_.size(); ++t) {
    if (tally.total[t] == 0) continue;
    const std::size_t r = scene_order_[t];
    const std::size_t parent = refined_ ? refined_->input_face[r] : r;
    const double area = norm(face_normal_unnormalized(rendered, rendered.faces[r]));
    const double v = static_cast<double>(tally.seen[t]) / static_cast<double>(tally.total[t]);
    // A sub-face of zero area still decides a face that has nothing else.
    const double w = area > 0 ? area : 1e-300;
    weighted[parent] += w * v;
    weight[parent] += w;
  }
  out.face.assign(input_faces, 0.0f);
  std::vector<bool> defined(input_faces, false);
  std::vector<double> vertex_weighted(input_.num_vertices(), 0.0), vertex_weight(input_.num_vertices(), 0.0);
  for (std::size_t f = 0; f < input_faces; ++f) {
    if (weight[f] == 0 || is_degenerate(input_, input_.faces[f])) continue;
    defined[f] = true;
    out.face[f] = static_cast<float>(std::clamp(weighted[f] / weight[f], 0.0, 1.0));
    const double area = norm(face_normal_unnormalized(input_, input_.faces[f]));
    for (VertexIndex v : input_.faces[f]) {
      vertex_weighted[v] += area * out.face[f];
      vertex_weight[v] += area;
    }
  }
  out.vertex.assign(input_.num_vertices(), 0.0f);
  for (std::size_t v = 0; v < out.vertex.size(); ++v) {
    if (vertex_weight[v] > 0) out.vertex[v] = static_cast<float>(std::clamp(vertex_weighted[v] / vertex_weight[v], 0.0, 1.0));
  }
  // Faces without a value of their own take the mean of their vertices.
  double area_sum = 0, visible_sum = 0, hidden_area = 0;
  for (std::size_t f = 0; f < input_faces; ++f) {
    const Face& face = input_.faces[f];
    if (!defined[f]) {
      if (!is_degenerate(input_, face)) ++out.stats.unfaced_faces;
      double sum = 0;
      int count = 0;
      for (VertexIndex v : face) {
        if (vertex_weight[v] > 0) {
          sum += out.vertex[v];
          ++count;
        }
      }
      out.face[f] = count > 0 ? static_cast<float>(sum / count) : 0.0f;
    }
    const double area = norm(face_normal_unnormalized(input_, face));
    area_sum += area;
    visible_sum += area * out.face[f];
    if (out.face[f] == 0.0f) {
      ++out.stats.hidden_faces;
      hidden_area += area;
    }
  }
  out.stats.hidden_area_fraction = area_sum > 0 ? hidden_area / area_sum : 0.0;
  out.mesh = area_sum > 0 ? visible_sum / area_sum : 0.0;
  out.stats.seconds_aggregate = seconds_since(start);
  return out;
}

VisibilityOptions options_of(const TallyKey& key) {
  VisibilityOptions options;
  options.fractional = (key.flags & TallyKey::kFractional) != 0;
  options.depth_test = (key.flags & TallyKey::kDepthTest) != 0;
  options.refine = (key.flags & TallyKey::kNoRefine) == 0;
  options.worst_view_cosine = key.worst_view_cosine;
  options.depth_tolerance_pixels = key.depth_tolerance_pixels;
  return options;
}

Rgb visibility_color(double v) {
  v = std::clamp(std::isfinite(v) ? v : 0.0, 0.0, 1.0);
  auto mix = [](Rgb a, Rgb b, double t) {
    Rgb c;
    for (int k = 0; k < 3; ++k) c[k] = static_cast<std::uint8_t>(std::lround(a[k] + (b[k] - a[k]) * t));
    return c;
  };
  const Rgb white{255, 255, 255}, red{220, 0, 0}, yellow{240, 220, 0}, green{0, 170, 0};
  if (v < 1.0 / 3) return mix(white, red, 3 * v);
  if (v < 2.0 / 3) return mix(red, yellow, 3 * v - 1);
  return mix(yellow, green, 3 * v - 2);
}

RgbImage render_visibility_map(const Mesh& mesh, const std::vector<float>& face_visibility, int size) {
  std::vector<Rgb> colors(mesh.num_faces());
  for (std::size_t f = 0; f < colors.size(); ++f) colors[f] = visibility_color(face_visibility[f]);
  return render_face_colors(mesh, colors, size);
}

Visibility compute_visibility(const Mesh& mesh, const CameraSet& cameras, Renderer& renderer,
                              const VisibilityOptions& options, RenderObserver* observer) {
  const auto start = std::chrono::steady_clock::now();
  VisibilityJob job(mesh, renderer.resolution(), options);
  const auto render_start = std::chrono::steady_clock::now();
  const VisibilityTally tally = job.render(cameras, 0, cameras.size(), renderer, observer);
  const double render_seconds = seconds_since(render_start);
  Visibility out = job.finish(tally);
  out.stats.seconds_render = render_seconds;
  out.stats.seconds_total = seconds_since(start);
  return out;
}

HiddenRemoval drop_hidden_faces(const Mesh& mesh, const std::vector<float>& face_visibility, double threshold) {
  if (face_visibility.size() != mesh.num_faces()) {
    throw UsageError("dropping hidden faces needs V of every face: got " + std::to_string(face_visibility.size()) +
                     " values for " + std::to_string(mesh.num_faces()) + " faces");
  }
  if (!(threshold >= 0 && threshold < 1)) throw UsageError("--drop-hidden threshold must be in [0, 1)");
  HiddenRemoval r;
  std::vector<std::uint8_t> keep(mesh.num_faces(), 0);
  double total_area = 0;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const double area = 0.5 * norm(face_normal_unnormalized(mesh, mesh.faces[f]));
    total_area += area;
    keep[f] = face_visibility[f] > threshold;
    if (keep[f]) {
      r.face_visibility.push_back(face_visibility[f]);
    } else {
      ++r.faces_removed;
      r.area_removed += area;
    }
  }
  r.mesh = keep_faces(mesh, keep);
  r.area_fraction_removed = total_area > 0 ? r.area_removed / total_area : 0.0;
  return r;
}

Visibility visibility_from_face_quality(const Mesh& input) {
  if (input.face_quality.size() != input.num_faces()) {
    throw InvalidMeshError("the input has no face quality to read V from");
  }
  Visibility v;
  v.face = input.face_quality;
  double weighted = 0, area = 0;
  for (std::size_t f = 0; f < input.num_faces(); ++f) {
    const float q = v.face[f];
    if (!(q >= 0.0f && q <= 1.0f)) {
      throw InvalidMeshError("face quality of face " + std::to_string(f) + " is " + std::to_string(q) +
                             ", not a visibility in [0, 1]");
    }
    const double a = 0.5 * norm(face_normal_unnormalized(input, input.faces[f]));
    weighted += a * q;
    area += a;
  }
  v.mesh = area > 0 ? weighted / area : 0.0;
  return v;
}

}  // namespace visimp
