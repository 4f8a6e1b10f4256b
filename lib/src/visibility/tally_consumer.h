// The per-camera half of the visibility measure (visibility.cpp has the rest), internal to
// the library.
//
// Per camera, on the worker that rendered the frame:
//   1. every pixel marks the face it shows as seen (binary F: the frame's number in
//      `seen_in_frame`, so nothing needs clearing; fractional F: a pixel count in `owned`);
//   2. depth test (mark_seen_vertices): a vertex counts as visible when it is no more than
//      the tolerance behind the surface interpolated from the four depths around it, or sits on
//      a silhouette or a corner of a face shown there; vertices whose faces all turn away are
//      skipped;
//   3. one pass over the faces adds q(R·N) to `seen` when the face owns a pixel or one of
//      its vertices is visible;
//   4. (fractional F only) the counts are cleared through the same pixels.
// Workers add integers into their own arrays, summed at the end: any thread count gives
// the same bits. `total`, the sum of q(R·N) over the cameras, depends on the face normal
// alone: it is added once per face after the frames (add_to), from the directions of the
// frames consumed, instead of being read and written in every frame's face pass.
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
  struct Worker {
    std::vector<std::uint32_t> seen;           // front side, every face: sum of q where seen
    std::vector<std::uint32_t> seen_back;      // back side, faces from one_sided_faces on
    std::vector<std::array<float, 3>> directions;  // of the frames consumed (for the totals)
    std::vector<std::uint16_t> owned;          // fractional F: pixels owned in the current frame (saturating)
    std::vector<std::uint32_t> seen_in_frame;  // binary F, by pixel id (0: background): last frame owning a pixel
    std::uint32_t frame_number = 0;
    std::vector<std::uint8_t> vertex_seen;       // per vertex: passes the depth test in this frame
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
    if (w.seen_in_frame.empty()) {
      w.seen.resize(faces);
      w.seen_back.resize(faces - one_sided_);
      if (options_.fractional) w.owned.assign(faces, 0);
      w.seen_in_frame.assign(faces + 1, 0);
      w.vertex_seen.assign(scene_.positions.size(), 0);
      if (options_.depth_test) {
        w.facing_vertices.resize(scene_.positions.size());
        w.unsure_vertices.resize(scene_.positions.size());
      }
    }
    const std::array<float, 3> direction = to_float3(frame.view.direction);
    w.directions.push_back(direction);
    const std::uint32_t* ids = frame.ids.data();
    const std::size_t pixels = frame.ids.size();
    const std::uint32_t frame_number = ++w.frame_number;
    if (options_.fractional) {
      for (std::size_t p = 0; p < pixels; ++p) {
        if (ids[p] != 0 && w.owned[ids[p] - 1] != 0xffffu) ++w.owned[ids[p] - 1];
      }
    } else {
      std::uint32_t* seen = w.seen_in_frame.data();
      for (std::size_t p = 0; p < pixels; ++p) seen[ids[p]] = frame_number;  // no branch on the background
    }
    if (options_.depth_test) mark_seen_vertices(frame, w);

    for (std::size_t first = 0; first < faces; first += RenderScene::kClusterSize) {
      // No face of such a cluster has weight for this camera (never set for two-sided faces).
      if (scene_.clusters[first / RenderScene::kClusterSize].all_back_facing(direction)) continue;
      const std::size_t last = std::min(faces, first + RenderScene::kClusterSize);
      const std::size_t split = std::clamp(one_sided_, first, last);  // one-sided faces first
      if (options_.fractional) {
        tally_faces<true, false>(first, split, direction, frame, w);
        tally_faces<true, true>(split, last, direction, frame, w);
      } else {
        tally_faces<false, false>(first, split, direction, frame, w);
        tally_faces<false, true>(split, last, direction, frame, w);
      }
    }
    if (options_.fractional) {
      for (std::size_t p = 0; p < pixels; ++p) {
        if (ids[p] != 0) w.owned[ids[p] - 1] = 0;
      }
    }
  }

  // F per face of [first, last): it owns a pixel, or one of its vertices passed the depth
  // test (vertex_seen stays all zero with the test off). One instance per kind of face, so
  // the common one (binary F, one side) is a tight loop without data-dependent branches: a
  // side with q = 0 adds nothing anyway.
  template <bool Fractional, bool TwoSided>
  void tally_faces(std::size_t first, std::size_t last, const std::array<float, 3>& direction, const Frame& frame,
                   Worker& w) const {
    // Local pointers: the compiler cannot prove the tallies do not alias the inputs.
    const Face* face = scene_.faces.data();
    const std::array<float, 3>* normal = face_normals_.data();
    const std::uint32_t* owned_in_frame = w.seen_in_frame.data() + 1;  // by face, not by id
    const std::uint8_t* vertex_seen = w.vertex_seen.data();
    const std::uint32_t frame_number = w.frame_number;
    std::uint32_t* front = w.seen.data();
    std::uint32_t* back = w.seen_back.data();  // scene faces from one_sided_ on
    for (std::size_t t = first; t < last; ++t) {
      const Face& f = face[t];
      const float cosine = dot(normal[t], direction);
      const bool owns = Fractional ? w.owned[t] != 0 : owned_in_frame[t] == frame_number;
      const bool visible = owns | ((vertex_seen[f[0]] | vertex_seen[f[1]] | vertex_seen[f[2]]) != 0);
      // Masks, not `visible ? q : 0`, which compiles to a branch that is a coin toss on a scan.
      const std::uint32_t mask = 0u - static_cast<std::uint32_t>(visible);
      const std::uint32_t q = quantized(cosine);
      if (Fractional) {
        front[t] += visible ? fractional_weight(t, q, frame, w) : 0u;
      } else {
        front[t] += q & mask;
      }
      if (TwoSided) {
        const std::uint32_t qb = quantized(-cosine);
        std::uint32_t& b = back[t - one_sided_];
        if (Fractional) {
          b += visible ? fractional_weight(t, qb, frame, w) : 0u;
        } else {
          b += qb & mask;
        }
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

  /// Sum of all workers' tallies, and the totals of the frames they consumed.
  void add_to(VisibilityTally& out) const {
    for (const Worker& w : workers_) {
      for (std::size_t t = 0; t < w.seen.size(); ++t) out.seen[t] += w.seen[t];
      for (std::size_t t = 0; t < w.seen_back.size(); ++t) out.seen_back[t] += w.seen_back[t];
    }
    add_totals(out);
  }

 private:
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
  void mark_seen_vertices(const Frame& frame, Worker& w) const {
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
    std::fill(seen, seen + vertex_count, std::uint8_t{0});
    constexpr std::size_t kRun = RenderScene::kClusterSize;
    if (scene_.vertex_cones.size() == vertex_count && scene_.vertex_clusters.size() * kRun >= vertex_count) {
      for (std::size_t first = 0; first < vertex_count; first += kRun) {
        if (scene_.vertex_clusters[first / kRun].all_back_facing(direction)) continue;  // a run at once
        const std::size_t last = std::min(vertex_count, first + kRun);
        for (std::size_t i = first; i < last; ++i) {
          facing[facing_count] = static_cast<std::uint32_t>(i);
          facing_count += static_cast<std::size_t>(!cones[i].all_back_facing(direction));
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
      seen[i] = static_cast<std::uint8_t>(in_front);
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
      seen[i] =
          static_cast<std::uint8_t>(seen[i] | shows_corner(faces, ids[p], i) | shows_corner(faces, ids[p + 1], i) |
                                    shows_corner(faces, ids[p + row], i) | shows_corner(faces, ids[p + row + 1], i));
    }
  }

  // total += Σ q(R·N) over the consumed frames' directions R, and total_back += Σ q(−R·N) for
  // the two-sided faces: the same floats and quantisation as the per-frame pass (quantize_weight;
  // a face of a cluster skipped as turned away has q = 0 there), so the same integers.
  void add_totals(VisibilityTally& out) const {
    std::vector<std::array<float, 3>> directions;
    for (const Worker& w : workers_) directions.insert(directions.end(), w.directions.begin(), w.directions.end());
    const std::size_t faces = scene_.faces.size();
    if (directions.empty()) return;
    constexpr std::size_t kChunk = 2048;  // the chunk's normals and sums stay in L1
    const std::size_t chunks = (faces + kChunk - 1) / kChunk;
    const unsigned workers = worker_count(static_cast<unsigned>(workers_.size()), chunks);
    parallel_for(0, chunks, workers, [&](unsigned, std::size_t chunk) {
      const std::size_t first = chunk * kChunk, count = std::min(faces, first + kChunk) - first;
      // One array per axis, cameras outside and faces inside: the face loop vectorises.
      alignas(64) float nx[kChunk], ny[kChunk], nz[kChunk];
      alignas(64) std::uint32_t front[kChunk] = {}, back[kChunk] = {};
      for (std::size_t i = 0; i < count; ++i) {
        nx[i] = face_normals_[first + i][0];
        ny[i] = face_normals_[first + i][1];
        nz[i] = face_normals_[first + i][2];
      }
      for (const std::array<float, 3>& d : directions) {
        const float dx = d[0], dy = d[1], dz = d[2];
        for (std::size_t i = 0; i < count; ++i) {
          const float cosine = nx[i] * dx + ny[i] * dy + nz[i] * dz;  // as dot(normal, direction)
          front[i] += quantized(cosine);
          back[i] += quantized(-cosine);
        }
      }
      for (std::size_t i = 0; i < count; ++i) {
        const std::size_t t = first + i;
        out.total[t] += front[i];
        if (t >= one_sided_) out.total_back[t - one_sided_] += back[i];
      }
    });
  }

  // quantize_weight with the clamp at zero moved after a signed conversion: for w < 0 the
  // rounded value truncates to at most 0, so the same integer. A float compare-and-select
  // becomes a branch or keeps a loop scalar (it may trap); an integer one does neither.
  static std::uint32_t quantized(float w) {
    const auto q = static_cast<std::int32_t>(w * static_cast<float>(VisibilityTally::kMaxWeight) + 0.5f);
    return static_cast<std::uint32_t>(q < 0 ? 0 : q);
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
