// The per-camera half of the visibility measure (visibility.cpp has the rest), internal to
// the library.
//
// Per camera, on the worker that rendered the frame:
//   1. every pixel marks the face it shows as seen (binary F: bit j of `owned_bits` for
//      frame j of the worker's current batch; fractional F: a pixel count in `owned`);
//   2. depth test (mark_seen_vertices): a vertex counts as visible when it is no more than
//      the tolerance behind the surface interpolated from the four depths around it, or sits on
//      a silhouette or a corner of a face shown there (the same bit in `vertex_seen`);
//      vertices whose faces all turn away are skipped;
//   3. a pass over the faces adds q(R·N) to `seen` when the face owns a pixel or one of its
//      vertices is visible: binary F once per batch of 8 frames, one bit and one lane each
//      (the pass is bound by its loads of faces and normals, now read once per 8 frames);
//      fractional F frame by frame, after which its counts are cleared through the pixels.
// `total`, the sum of q(R·N) over the cameras, is added in the same face pass (the cosines
// are at hand there). Workers add integers into their own arrays, summed at the end (after
// each worker's last, partial batch): any thread count and any batching give the same bits.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "visimp/core/parallel.h"
#include "visimp/render/frame.h"
#include "visimp/render/renderer.h"
#include "visimp/visibility/tally.h"
#include "visimp/visibility/visibility.h"

namespace visimp::detail {

inline std::array<float, 3> to_float3(const Vec3& v) {
  return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
}

inline float dot(const std::array<float, 3>& a, const std::array<float, 3>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// Per-worker accumulators; see the file comment for the four steps.
class TallyConsumer final : public FrameConsumer {
  // Binary F tallies the faces once per batch of this many frames (one bit each).
  static constexpr std::size_t kBatch = 8;

  struct Sums {
    std::uint32_t seen = 0, total = 0;  // Σ q where seen, Σ q: together, one cache line serves both
  };

  struct Worker {
    std::vector<Sums> front;                   // every face
    std::vector<Sums> back;                    // faces from one_sided_faces on
    std::array<std::array<float, 3>, kBatch> directions;  // of the current batch's frames
    std::vector<std::uint16_t> owned;          // fractional F: pixels owned in the current frame (saturating)
    std::vector<std::uint8_t> owned_bits;      // binary F, by pixel id (0: background): bit j, owned in frame j
    std::vector<std::uint8_t> vertex_seen;     // per vertex: bit j, passes the depth test in frame j
    std::size_t batched = 0;                   // frames in the current batch (binary F)
    std::vector<std::uint32_t> facing_vertices;  // the depth test's first pass
    std::vector<std::uint32_t> unsure_vertices;  // the depth test's second pass
  };

 public:
  TallyConsumer(const RenderScene& scene, const std::vector<std::array<float, 3>>& face_normals,
                std::size_t one_sided_faces, const VisibilityOptions& options)
      : scene_(scene), face_normals_(face_normals), one_sided_(one_sided_faces), options_(options) {}

  void begin(unsigned workers) override { workers_.resize(workers); }

  void consume(const Frame& frame, std::size_t, unsigned worker) override {
    Worker& w = workers_[worker];
    const std::size_t faces = scene_.faces.size();
    if (w.vertex_seen.empty()) {
      w.front.resize(faces);
      w.back.resize(faces - one_sided_);
      if (options_.fractional) {
        w.owned.assign(faces, 0);
      } else {
        w.owned_bits.assign(faces + 1, 0);
      }
      w.vertex_seen.assign(scene_.positions.size(), 0);
      if (options_.depth_test) {
        w.facing_vertices.resize(scene_.positions.size());
        w.unsure_vertices.resize(scene_.positions.size());
      }
    }
    const std::array<float, 3> direction = to_float3(frame.view.direction);
    w.directions[w.batched] = direction;
    const std::uint32_t* ids = frame.ids.data();
    const std::size_t pixels = frame.ids.size();
    // Fractional F is tallied frame by frame (bit 0); binary F frame j of a batch is bit j.
    const auto bit = static_cast<std::uint8_t>(1u << w.batched);
    if (options_.fractional) {
      for (std::size_t p = 0; p < pixels; ++p) {
        if (ids[p] != 0 && w.owned[ids[p] - 1] != 0xffffu) ++w.owned[ids[p] - 1];
      }
    } else {
      std::uint8_t* owned = w.owned_bits.data();
      for (std::size_t p = 0; p < pixels; ++p) owned[ids[p]] |= bit;  // no branch on the background
    }
    if (options_.depth_test) mark_seen_vertices(frame, bit, w);

    if (options_.fractional) {
      tally_frame(direction, frame, w);
      for (std::size_t p = 0; p < pixels; ++p) {
        if (ids[p] != 0) w.owned[ids[p] - 1] = 0;
      }
      std::fill(w.vertex_seen.begin(), w.vertex_seen.end(), std::uint8_t{0});
    } else if (++w.batched == kBatch) {
      tally_batch(w);
    }
  }

  /// Sum of all workers' tallies, after each one's last, partial batch.
  void add_to(VisibilityTally& out) {
    parallel_for(0, workers_.size(), static_cast<unsigned>(workers_.size()), [&](unsigned, std::size_t i) {
      if (workers_[i].batched > 0) tally_batch(workers_[i]);
    });
    for (const Worker& w : workers_) {
      for (std::size_t t = 0; t < w.front.size(); ++t) {
        out.seen[t] += w.front[t].seen;
        out.total[t] += w.front[t].total;
      }
      for (std::size_t t = 0; t < w.back.size(); ++t) {
        out.seen_back[t] += w.back[t].seen;
        out.total_back[t] += w.back[t].total;
      }
    }
  }

 private:
  // Fractional F and the totals for one frame: q times the fraction of the face's pixels it owns.
  void tally_frame(const std::array<float, 3>& direction, const Frame& frame, Worker& w) const {
    const std::size_t faces = scene_.faces.size();
    for (std::size_t first = 0; first < faces; first += RenderScene::kClusterSize) {
      // No face of such a cluster has weight for this camera (never set for two-sided faces).
      if (scene_.clusters[first / RenderScene::kClusterSize].all_back_facing(direction)) continue;
      const std::size_t last = std::min(faces, first + RenderScene::kClusterSize);
      const Face* face = scene_.faces.data();
      const std::uint8_t* vertex_seen = w.vertex_seen.data();
      for (std::size_t t = first; t < last; ++t) {
        const Face& f = face[t];
        const float cosine = dot(face_normals_[t], direction);
        const std::uint32_t q = quantize_weight(cosine), q_back = quantize_weight(-cosine);
        w.front[t].total += q;
        if (t >= one_sided_) w.back[t - one_sided_].total += q_back;
        const bool visible = w.owned[t] != 0 || (vertex_seen[f[0]] | vertex_seen[f[1]] | vertex_seen[f[2]]) != 0;
        if (!visible) continue;
        w.front[t].seen += fractional_weight(t, q, frame, w);
        if (t >= one_sided_) w.back[t - one_sided_].seen += fractional_weight(t, q_back, frame, w);
      }
    }
  }

  // Binary F and the totals for the frames of the batch, one pass over the faces for all of
  // them (the face data is read once per batch, not once per frame: the pass is bound by its
  // loads). A face is seen in frame j when it owns a pixel there or one of its vertices
  // passed the depth test (bit j). Unused lanes have direction 0, so q = 0 there.
  void tally_batch(Worker& w) const {
    const std::size_t frames = w.batched, faces = scene_.faces.size();
    alignas(16) float dx[kBatch] = {}, dy[kBatch] = {}, dz[kBatch] = {};
    const std::array<float, 3>* batch = w.directions.data();
    for (std::size_t j = 0; j < frames; ++j) {
      dx[j] = batch[j][0];
      dy[j] = batch[j][1];
      dz[j] = batch[j][2];
    }
    for (std::size_t first = 0; first < faces; first += RenderScene::kClusterSize) {
      const NormalCone& cluster = scene_.clusters[first / RenderScene::kClusterSize];
      bool all_away = true;  // no face of the cluster has weight for any camera of the batch
      for (std::size_t j = 0; j < frames; ++j) all_away = all_away && cluster.all_back_facing(batch[j]);
      if (all_away) continue;
      const std::size_t last = std::min(faces, first + RenderScene::kClusterSize);
      const std::size_t split = std::clamp(one_sided_, first, last);  // one-sided faces first
      tally_faces<false>(first, split, dx, dy, dz, w);
      tally_faces<true>(split, last, dx, dy, dz, w);
    }
    std::fill(w.owned_bits.begin(), w.owned_bits.end(), std::uint8_t{0});
    std::fill(w.vertex_seen.begin(), w.vertex_seen.end(), std::uint8_t{0});
    w.batched = 0;
  }

  // The faces of [first, last), one kind at a time, without data-dependent branches: a side
  // with q = 0 adds nothing anyway. The lanes are the frames of the batch (they vectorise).
  template <bool TwoSided>
  void tally_faces(std::size_t first, std::size_t last, const float* dx, const float* dy, const float* dz,
                   Worker& w) const {
    // Local pointers: the compiler cannot prove the tallies do not alias the inputs.
    const Face* face = scene_.faces.data();
    const std::array<float, 3>* normal = face_normals_.data();
    const std::uint8_t* owned = w.owned_bits.data() + 1;  // by face, not by id
    const std::uint8_t* vertex_seen = w.vertex_seen.data();
    Sums* front = w.front.data();
    Sums* back = w.back.data();  // scene faces from one_sided_ on
    for (std::size_t t = first; t < last; ++t) {
      const Face& f = face[t];
      const std::uint32_t visible = owned[t] | vertex_seen[f[0]] | vertex_seen[f[1]] | vertex_seen[f[2]];
      const float nx = normal[t][0], ny = normal[t][1], nz = normal[t][2];
      std::uint32_t seen = 0, total = 0, seen_back = 0, total_back = 0;
      for (std::size_t j = 0; j < kBatch; ++j) {
        const float cosine = nx * dx[j] + ny * dy[j] + nz * dz[j];  // as dot(normal, direction)
        // A mask, not `seen ? q : 0`, which compiles to a branch that is a coin toss on a scan.
        const std::uint32_t mask = 0u - ((visible >> j) & 1u);
        const std::uint32_t q = quantize_weight(cosine);
        seen += q & mask;
        total += q;
        if (TwoSided) {
          const std::uint32_t q_back = quantize_weight(-cosine);
          seen_back += q_back & mask;
          total_back += q_back;
        }
      }
      front[t].seen += seen;
      front[t].total += total;
      if (TwoSided) {
        back[t - one_sided_].seen += seen_back;
        back[t - one_sided_].total += total_back;
      }
    }
  }

  // Fractional F: q times the fraction of the projected area that owns pixels; a face
  // smaller than a pixel that is seen at all counts as wholly seen.
  std::uint32_t fractional_weight(std::size_t t, std::uint32_t q, const Frame& frame, const Worker& w) const {
    if (q == 0) return 0;
    const Face& f = scene_.faces[t];
    const ScreenVertex &a = frame.vertices[f[0]], &b = frame.vertices[f[1]], &c = frame.vertices[f[2]];
    const float area = 0.5f * std::abs((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
    const float fraction = std::min(1.0f, std::max(static_cast<float>(w.owned[t]), 1.0f) / std::max(area, 1.0f));
    return static_cast<std::uint32_t>(static_cast<float>(q) * fraction + 0.5f);
  }

  // The depth test of one vertex against the surface drawn at the four pixel centres
  // around it (docs/visibility.md, "The depth test"). The vertex is seen when
  //   - it is no more than the tolerance behind the bilinear interpolation of the four
  //     depths at the vertex (the surface shown there; exact for a plane, so a face's own
  //     slope needs no allowance), or
  //   - one of the four pixels shows the background (it sits on a silhouette) or a face
  //     that has the vertex as a corner (it lies on the surface shown there).
  // A slope allowance from the face's own angle, as before, let anything up to ~3 px
  // behind a thin shell count as seen at grazing views; extending the planes of the faces
  // shown instead fails on sub-pixel slivers of rounded edges, whose planes tilt anywhere.
  // Sets `bit` in vertex_seen for the vertices seen in this frame.
  void mark_seen_vertices(const Frame& frame, std::uint8_t bit, Worker& w) const {
    const int size = frame.resolution();
    const auto row = static_cast<std::size_t>(size);
    const float* depth = frame.depth.data();
    const std::uint32_t* ids = frame.ids.data();
    const float tolerance = static_cast<float>(options_.depth_tolerance_pixels) / static_cast<float>(size);
    // A face up to the worst viewing angle changes depth by at most `reach` over 0.71 px:
    // a vertex farther than that behind every sample is no corner of a face drawn there.
    const double c = options_.worst_view_cosine;
    const float reach = static_cast<float>(0.7072 * std::sqrt(1.0 - c * c) / c) / static_cast<float>(size);
    std::uint8_t* seen = w.vertex_seen.data();
    std::uint32_t* unsure = w.unsure_vertices.data();
    std::size_t unsure_count = 0;
    // Pass 0: the vertices with a face turned toward the camera, listed without a branch, after
    // skipping the runs of vertices turned away as a whole (the others' test cannot matter:
    // all their faces have q = 0; they are about 45% of the dragon's vertices per camera, and
    // pass 1 is bound by its loads).
    const std::array<float, 3> direction = to_float3(frame.view.direction);
    const VertexCone* cones = scene_.vertex_cones.data();
    const std::size_t vertex_count = frame.vertices.size();
    std::uint32_t* facing = w.facing_vertices.data();
    std::size_t facing_count = 0;
    constexpr std::size_t kRun = RenderScene::kClusterSize;
    if (scene_.vertex_cones.size() == vertex_count && scene_.vertex_clusters.size() * kRun >= vertex_count) {
      for (std::size_t first = 0; first < vertex_count; first += kRun) {
        if (scene_.vertex_clusters[first / kRun].all_back_facing(direction)) continue;  // a run at once
        const std::size_t count = std::min(vertex_count, first + kRun) - first;
        // The cone tests in a loop of their own (it vectorises), then the list.
        std::array<std::uint8_t, kRun> turned_toward;
        for (std::size_t k = 0; k < count; ++k) turned_toward[k] = !cones[first + k].all_back_facing(direction);
        for (std::size_t k = 0; k < count; ++k) {
          facing[facing_count] = static_cast<std::uint32_t>(first + k);
          facing_count += turned_toward[k];
        }
      }
    } else {
      for (std::size_t i = 0; i < vertex_count; ++i) facing[i] = static_cast<std::uint32_t>(i);
      facing_count = vertex_count;
    }
    // Pass 1, branch-free (which case a vertex falls in is a coin toss on a scan): behind the
    // bilinear surface (which is never nearer than the nearest sample) or not; the vertices
    // neither clearly seen nor clearly hidden are kept for pass 2.
    const ScreenVertex* screen = frame.vertices.data();
    for (std::size_t k = 0; k < facing_count; ++k) {
      const std::uint32_t i = facing[k];
      const ScreenVertex& v = screen[i];
      // Screen coordinates are positive, so truncation is the floor (or 0 where clamped anyway).
      const int px = std::min(static_cast<int>(v.x - 0.5f), size - 2);
      const int py = std::min(static_cast<int>(v.y - 0.5f), size - 2);
      const std::size_t p = static_cast<std::size_t>(py) * row + static_cast<std::size_t>(px);
      const float d0 = depth[p], d1 = depth[p + 1], d2 = depth[p + row], d3 = depth[p + row + 1];
      // min(max()), not std::clamp: minss/maxss rather than compares and jumps.
      const float fx = std::min(std::max(v.x - 0.5f - static_cast<float>(px), 0.0f), 1.0f);
      const float fy = std::min(std::max(v.y - 0.5f - static_cast<float>(py), 0.0f), 1.0f);
      const float below = d0 + (d1 - d0) * fx, above = d2 + (d3 - d2) * fx;
      const float z = v.depth - tolerance;
      const bool in_front = z <= below + (above - below) * fy;
      const bool near = z <= std::max(std::max(d0, d1), std::max(d2, d3)) + reach;
      seen[i] = static_cast<std::uint8_t>(seen[i] | (bit & (0u - static_cast<unsigned>(in_front))));
      unsure[unsure_count] = i;
      unsure_count += static_cast<std::size_t>(!in_front & near);
    }
    // Pass 2: on a silhouette (background next to it) or a corner of a face shown next to it.
    const Face* faces = scene_.faces.data();
    for (std::size_t k = 0; k < unsure_count; ++k) {
      const std::uint32_t i = unsure[k];
      const ScreenVertex& v = frame.vertices[i];
      const int px = std::min(static_cast<int>(v.x - 0.5f), size - 2);
      const int py = std::min(static_cast<int>(v.y - 0.5f), size - 2);
      const std::size_t p = static_cast<std::size_t>(py) * row + static_cast<std::size_t>(px);
      // All four tested at once, not one after another: the face loads are the cost here.
      const unsigned corner = shows_corner(faces, ids[p], i) | shows_corner(faces, ids[p + 1], i) |
                              shows_corner(faces, ids[p + row], i) | shows_corner(faces, ids[p + row + 1], i);
      seen[i] = static_cast<std::uint8_t>(seen[i] | (bit & (0u - corner)));
    }
  }

  // The pixel shows the background, or a face with corner i.
  static std::uint8_t shows_corner(const Face* faces, std::uint32_t id, std::uint32_t i) {
    const Face& f = faces[id != 0 ? id - 1 : 0];
    // int, not bool, operands: all four compared without branches.
    return static_cast<std::uint8_t>(int{id == 0} | int{f[0] == i} | int{f[1] == i} | int{f[2] == i});
  }

  const RenderScene& scene_;
  const std::vector<std::array<float, 3>>& face_normals_;
  std::size_t one_sided_;
  const VisibilityOptions& options_;
  std::vector<Worker> workers_;
};

}  // namespace visimp::detail
