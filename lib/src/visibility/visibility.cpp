// The visibility measure (see visibility.h; Zhang & Turk 2002, eqs. 3.2 and 4.3): the job
// that prepares a mesh (winding, refinement, scene order), renders camera slices through
// TallyConsumer (tally_consumer.h: per-camera F and the depth test) and turns tallies into V.
#include "visimp/visibility/visibility.h"
#include "visimp/core/stopwatch.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>

#include "visimp/core/bounding_box.h"
#include "visimp/core/content_hash.h"
#include "visimp/core/face_subset.h"
#include "visimp/core/spatial_order.h"
#include "visimp/core/errors.h"
#include "visimp/core/mesh_stats.h"
#include "visimp/core/orientation.h"
#include "visimp/core/parallel.h"
#include "visimp/core/union_find.h"
#include "tally_consumer.h"

namespace visimp {
namespace {

std::uint64_t hash_cameras(const CameraSet& cameras) { return hash_directions(cameras.directions); }

// Per-face loops run over ranges of this many faces (or vertices) on the job's threads.
constexpr std::size_t kFaceRange = 1 << 14;

// `body(i)` for i in [0, n), ranges in parallel: bodies write only item i's outputs.
template <typename Body>
void for_face_ranges(std::size_t n, unsigned workers, const Body& body) {
  parallel_ranges(n, kFaceRange, workers, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) body(i);
  });
}

std::array<float, 3> to_float(const Vec3& v) {
  return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
}

}  // namespace

std::vector<OptionSpec> describe_options(VisibilityOptions& o) {
  return {
      option_spec("--worst-view-cosine", "C", o.worst_view_cosine,
                  "cosine of the worst viewing angle; edges longer than pixel/C are split, (0, 1]"),
      negated_switch_spec("--no-refine", o.refine, "do not split long edges (to study the effect)"),
      negated_switch_spec("--no-depth-test", o.depth_test, "only pixel ownership decides F (to study the effect)"),
      option_spec("--depth-tolerance", "PX", o.depth_tolerance_pixels,
                  "how far behind the surface at a neighbouring pixel a vertex still counts as seen, [0, 16]"),
      switch_spec("--trust-winding", o.trust_winding,
                  "take the input's normals as outward: one-sided F as in the paper (no reorientation)"),
      switch_spec("--fractional", o.fractional, "F = visible fraction of the projected area instead of 0/1"),
      option_spec("--max-refined-faces", "N", o.max_refined_faces, "refuse to refine beyond N faces"),
  };
}

void check_options(const VisibilityOptions& o) {
  if (!(o.worst_view_cosine > 0 && o.worst_view_cosine <= 1))
    throw OptionError(&o.worst_view_cosine, "VisibilityOptions::worst_view_cosine", "must be in (0, 1]");
  if (!(o.depth_tolerance_pixels >= 0 && o.depth_tolerance_pixels <= 16))
    throw OptionError(&o.depth_tolerance_pixels, "VisibilityOptions::depth_tolerance_pixels",
                      "must be in [0, 16] pixels");
  if (o.max_refined_faces == 0)
    throw OptionError(&o.max_refined_faces, "VisibilityOptions::max_refined_faces", "must be positive");
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
  const std::size_t input_faces = mesh.num_faces();
  const unsigned workers = worker_count(options.threads, input_faces / kFaceRange + 1);
  // The hash (byte-serial FNV, ~0.6 s at 14M faces) runs beside the other stages; the future
  // waits for it even when a stage throws.
  std::future<std::uint64_t> hash =
      std::async(workers > 1 ? std::launch::async : std::launch::deferred, [&mesh] { return hash_mesh(mesh); });
  stats_.input_faces = input_faces;
  stats_.resolution = resolution;
  // Once per face (the winding and finish() ask again).
  input_degenerate_.resize(input_faces);
  for_face_ranges(input_faces, workers, [&](std::size_t f) {
    input_degenerate_[f] = is_degenerate(mesh, mesh.faces[f]) ? 1 : 0;
  });
  stats_.degenerate_faces = static_cast<std::size_t>(std::count(input_degenerate_.begin(), input_degenerate_.end(), 1));

  // Canonical winding (core/orientation.h): the faces rendered do not depend on the input's.
  input_reversed_.assign(input_faces, 0);
  input_one_sided_.assign(input_faces, 0);
  if (options.trust_winding) {
    std::fill(input_one_sided_.begin(), input_one_sided_.end(), back_faces_always_hidden(mesh) ? 1 : 0);
  } else {
    const OrientationPatches patches = orientation_patches(mesh, workers);
    for_face_ranges(input_faces, workers, [&](std::size_t f) {
      input_reversed_[f] = patches.reversed[f];
      input_one_sided_[f] = patches.closed[patches.patch_of_face[f]] && input_degenerate_[f] == 0 ? 1 : 0;
    });
  }
  auto wound_face = [&](std::size_t f) {
    return options.trust_winding ? mesh.faces[f] : canonical_face(mesh.faces[f], input_reversed_[f] != 0);
  };
  stats_.one_sided_faces = static_cast<std::size_t>(std::count(input_one_sided_.begin(), input_one_sided_.end(), 1));
  stats_.two_sided_faces = input_faces - stats_.one_sided_faces;

  stats_.seconds_orient = seconds_since(start);

  const auto refine_start = std::chrono::steady_clock::now();
  const BoundingBox box = bounding_box(mesh);
  const double radius = view_radius(box);
  stats_.max_edge_length = refinement_edge_length(radius, resolution, options.worst_view_cosine);
  if (options.refine && has_edge_longer_than(mesh, stats_.max_edge_length)) {
    Mesh wound{mesh.positions, std::vector<Face>(input_faces), {}, {}};
    for (std::size_t f = 0; f < input_faces; ++f) wound.faces[f] = wound_face(f);
    refined_ = refine_long_edges(std::move(wound), stats_.max_edge_length, options.max_refined_faces);
  }
  stats_.refinement_rounds = refined_ ? refined_->rounds : 0;
  const std::vector<Vec3>& positions = refined_ ? refined_->mesh.positions : mesh.positions;
  auto rendered_face = [&](std::size_t r) { return refined_ ? refined_->mesh.faces[r] : wound_face(r); };
  auto parent_of = [&](std::size_t r) { return refined_ ? refined_->input_face[r] : r; };
  const std::size_t faces_rendered = refined_ ? refined_->mesh.num_faces() : input_faces;
  stats_.refined_faces = faces_rendered;
  stats_.seconds_refine = seconds_since(refine_start);

  const auto scene_start = std::chrono::steady_clock::now();
  // The scene holds the faces in spatial order, one-sided ones first (they may be culled),
  // and the vertices in order of first use.
  scene_order_ = spatial_face_order(rendered_mesh(), workers);
  if (stats_.one_sided_faces != 0 && stats_.two_sided_faces != 0) {  // else every face is on the same side
    std::stable_partition(scene_order_.begin(), scene_order_.end(),
                          [&](std::uint32_t r) { return input_one_sided_[parent_of(r)] != 0; });
  }
  one_sided_scene_faces_ = stats_.two_sided_faces == 0 ? faces_rendered : 0;
  if (stats_.one_sided_faces != 0 && stats_.two_sided_faces != 0) {
    one_sided_scene_faces_ = static_cast<std::size_t>(std::partition_point(scene_order_.begin(), scene_order_.end(),
        [&](std::uint32_t r) { return input_one_sided_[parent_of(r)] != 0; }) - scene_order_.begin());
  }
  const Vec3 center = bounding_box(rendered_mesh()).center();
  scene_.radius = radius;
  scene_.faces.resize(faces_rendered);
  unit_normals_.resize(faces_rendered);
  // Faces and normals per face in parallel (input vertex numbers for now), then the vertices
  // numbered in order of first use: the one serial pass.
  for_face_ranges(faces_rendered, workers, [&](std::size_t t) {
    const Face f = rendered_face(scene_order_[t]);
    const bool degenerate = is_degenerate(positions, f);
    const Vec3 n = cross(positions[f[1]] - positions[f[0]], positions[f[2]] - positions[f[0]]);
    unit_normals_[t] = degenerate ? std::array<float, 3>{0, 0, 0} : to_float(n / norm(n));
    scene_.faces[t] = f;
  });
  constexpr VertexIndex kUnused = 0xffffffffu;
  std::vector<VertexIndex> scene_vertex(positions.size(), kUnused);
  std::vector<VertexIndex> source_vertex;  // scene vertex → rendered mesh's
  source_vertex.reserve(positions.size());
  for (Face& face : scene_.faces) {
    for (VertexIndex& corner : face) {
      VertexIndex& v = scene_vertex[corner];
      if (v == kUnused) {
        v = static_cast<VertexIndex>(source_vertex.size());
        source_vertex.push_back(corner);
      }
      corner = v;
    }
  }
  std::vector<VertexIndex>().swap(scene_vertex);
  scene_.positions.resize(source_vertex.size());
  for_face_ranges(source_vertex.size(), workers,
                  [&](std::size_t v) { scene_.positions[v] = to_float(positions[source_vertex[v]] - center); });
  std::vector<VertexIndex>().swap(source_vertex);
  scene_.culled_faces = one_sided_scene_faces_;
  stats_.back_faces_culled = scene_.culled_faces == faces_rendered && faces_rendered > 0;
  // Trusting the winding, every face is tallied from its front only (culled or not).
  if (options.trust_winding) {
    one_sided_scene_faces_ = faces_rendered;
    stats_.one_sided_faces = input_faces;
    stats_.two_sided_faces = 0;
  }
  scene_.compute_normal_cones(unit_normals_, workers);
  mesh_hash_ = hash.get();
  stats_.seconds_scene = seconds_since(scene_start);
  stats_.seconds_prepare = seconds_since(start);
}

TallyKey VisibilityJob::key(const CameraSet& cameras) const {
  TallyKey key;
  key.mesh_hash = mesh_hash_;
  key.camera_hash = hash_cameras(cameras);
  key.camera_count = cameras.size();
  key.faces = scene_.faces.size();
  key.one_sided_faces = one_sided_scene_faces_;
  key.resolution = static_cast<std::uint32_t>(resolution_);
  key.flags = (options_.fractional ? TallyKey::kFractional : 0) | (options_.depth_test ? TallyKey::kDepthTest : 0) |
              (options_.refine ? 0 : TallyKey::kNoRefine) | (options_.trust_winding ? TallyKey::kTrustWinding : 0);
  key.worst_view_cosine = options_.worst_view_cosine;
  key.depth_tolerance_pixels = options_.depth_tolerance_pixels;
  return key;
}

VisibilityTally VisibilityJob::render(const CameraSet& cameras, std::size_t first, std::size_t last, Renderer& renderer,
                                      RenderObserver* observer, FrameConsumer* also) const {
  if (cameras.size() == 0 || cameras.size() > VisibilityTally::kMaxCameras) {
    throw UsageError("a camera set needs 1..65536 cameras, got " + std::to_string(cameras.size()));
  }
  if (first > last || last > cameras.size()) {
    throw UsageError("camera range " + std::to_string(first) + ":" + std::to_string(last) +
                     " is outside 0:" + std::to_string(cameras.size()));
  }
  if (renderer.resolution() != resolution_) {
    throw UsageError("renderer resolution " + std::to_string(renderer.resolution()) + " differs from the job's " +
                     std::to_string(resolution_));
  }
  VisibilityTally tally;
  tally.key = key(cameras);
  if (first < last) tally.camera_ranges.emplace_back(first, last);
  tally.reset_sums();
  detail::TallyConsumer consumer(scene_, unit_normals_, one_sided_scene_faces_, options_);
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

  // Each side of an input face: V = area-weighted mean over its sub-faces that some camera
  // faced from that side. Side 0 is the canonical front (outward on closed surfaces).
  // (No back-side sums at all when every face is on a closed surface: the dragon's case.)
  const std::size_t back_sums = one_sided_scene_faces_ < scene_order_.size() ? input_faces : 0;
  // Float sums: a face has few sub-faces, and the dragon's finish would otherwise be its peak.
  std::vector<float> weighted[2] = {std::vector<float>(input_faces, 0.0f), std::vector<float>(back_sums, 0.0f)};
  std::vector<float> weight[2] = {std::vector<float>(input_faces, 0.0f), std::vector<float>(back_sums, 0.0f)};
  auto add_side = [&](int side, std::size_t parent, double area, std::uint32_t seen, std::uint32_t total) {
    if (total == 0) return;
    // A sub-face of zero area still decides a face that has nothing else.
    const double w = area > 0 ? area : 1e-30;
    weighted[side][parent] += static_cast<float>(w * static_cast<double>(seen) / static_cast<double>(total));
    weight[side][parent] += static_cast<float>(w);
  };
  const unsigned workers = worker_count(options_.threads, input_faces / kFaceRange + 1);
  // Unrefined, each scene face is its own input face's only part: no two write the same sums.
  for_face_ranges(scene_order_.size(), refined_ ? 1 : workers, [&](std::size_t t) {
    const std::size_t r = scene_order_[t];
    const std::size_t parent = refined_ ? refined_->input_face[r] : r;
    const double area = norm(face_normal_unnormalized(rendered, rendered.faces[r]));
    add_side(0, parent, area, tally.seen[t], tally.total[t]);
    if (t >= one_sided_scene_faces_) {
      add_side(1, parent, area, tally.seen_back[t - one_sided_scene_faces_],
               tally.total_back[t - one_sided_scene_faces_]);
    }
  });
  out.face_front.assign(input_faces, 0.0f);
  out.face_back.assign(input_faces, 0.0f);
  for_face_ranges(input_faces, workers, [&](std::size_t f) {
    float side[2] = {0.0f, 0.0f};
    for (int k = 0; k < (back_sums > 0 ? 2 : 1); ++k) {
      if (weight[k][f] > 0) side[k] = std::clamp(weighted[k][f] / weight[k][f], 0.0f, 1.0f);
    }
    const bool reversed = input_reversed_[f] != 0;
    out.face_front[f] = side[reversed ? 1 : 0];
    out.face_back[f] = side[reversed ? 0 : 1];
  });
  for (std::size_t f = 0; f < input_faces; ++f) out.stats.seen_from_behind += out.face_back[f] > out.face_front[f];
  out.face.assign(input_faces, 0.0f);
  std::vector<std::uint8_t> defined(input_faces, 0);
  for_face_ranges(input_faces, workers, [&](std::size_t f) {
    const bool faced = weight[0][f] > 0 || (back_sums > 0 && weight[1][f] > 0);
    if (!faced || input_degenerate_[f] != 0) return;
    defined[f] = 1;
    out.face[f] = std::max(out.face_front[f], out.face_back[f]);  // the better-seen side
  });
  // Vertex V: area-weighted over the defined faces around it. One range of vertices per
  // worker, each scanning every face and summing only its own corners, in face order: the
  // same sums for any thread count.
  const std::size_t nv = input_.num_vertices();
  std::vector<double> vertex_weighted(nv, 0.0), vertex_weight(nv, 0.0);
  const std::size_t per_worker = (nv + workers - 1) / workers;
  parallel_ranges(nv, std::max<std::size_t>(per_worker, 1), workers, [&](std::size_t first, std::size_t last) {
    for (std::size_t f = 0; f < input_faces; ++f) {
      if (defined[f] == 0) continue;
      const Face& face = input_.faces[f];
      if (std::none_of(face.begin(), face.end(), [&](VertexIndex v) { return v >= first && v < last; })) continue;
      const double area = norm(face_normal_unnormalized(input_, face));
      for (VertexIndex v : face) {
        if (v < first || v >= last) continue;
        vertex_weighted[v] += area * out.face[f];
        vertex_weight[v] += area;
      }
    }
  });
  out.vertex.assign(nv, 0.0f);
  for_face_ranges(nv, workers, [&](std::size_t v) {
    if (vertex_weight[v] > 0)
      out.vertex[v] = static_cast<float>(std::clamp(vertex_weighted[v] / vertex_weight[v], 0.0, 1.0));
  });
  // Faces without a value of their own take the mean of their vertices. V(M) and the hidden
  // share: sums per fixed range of faces, added in range order (any thread count, same bits).
  struct RangeSums {
    double area = 0, visible = 0, hidden_area = 0;
    std::size_t unfaced = 0, hidden = 0;
  };
  std::vector<RangeSums> range_sums((input_faces + kFaceRange - 1) / kFaceRange);
  parallel_ranges(input_faces, kFaceRange, workers, [&](std::size_t begin, std::size_t end) {
    RangeSums& sums = range_sums[begin / kFaceRange];
    for (std::size_t f = begin; f < end; ++f) {
      const Face& face = input_.faces[f];
      if (defined[f] == 0) {
        if (input_degenerate_[f] == 0) ++sums.unfaced;
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
      sums.area += area;
      sums.visible += area * out.face[f];
      if (out.face[f] == 0.0f) {
        ++sums.hidden;
        sums.hidden_area += area;
      }
    }
  });
  double area_sum = 0, visible_sum = 0, hidden_area = 0;
  for (const RangeSums& sums : range_sums) {
    area_sum += sums.area;
    visible_sum += sums.visible;
    hidden_area += sums.hidden_area;
    out.stats.unfaced_faces += sums.unfaced;
    out.stats.hidden_faces += sums.hidden;
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
  options.trust_winding = (key.flags & TallyKey::kTrustWinding) != 0;
  options.worst_view_cosine = key.worst_view_cosine;
  options.depth_tolerance_pixels = key.depth_tolerance_pixels;
  return options;
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
