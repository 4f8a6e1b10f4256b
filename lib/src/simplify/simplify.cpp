// Greedy edge collapse with quadric error metrics: Garland & Heckbert, "Surface
// Simplification Using Quadric Error Metrics", SIGGRAPH 1997 (§4–5), with the legality
// rules of Hoppe et al. 1993 (link condition) and area-weighted quadrics (Garland 1999 §3.4).
// Zhang & Turk 2002 §5 (eq. 5.6–5.7) is the QB baseline this reproduces.
#include "visimp/simplify/simplify.h"

#include <algorithm>
#include <limits>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <optional>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "visimp/core/bounding_box.h"
#include "visimp/core/errors.h"
#include "visimp/core/mesh_stats.h"
#include "visimp/core/parallel.h"
#include "visimp/core/spatial_order.h"
#include "visimp/core/union_find.h"
#include "visimp/core/validate.h"
#include "visimp/simplify/quadric.h"
#include "../core/large_array.h"
#include "radix_heap.h"
#include "vertex_face_lists.h"

namespace visimp {

std::vector<OptionSpec> describe_options(SimplifyOptions& o) {
  return {
      option_spec("--target", "N", o.target_faces, "stop at N faces or fewer (0: use --ratio)"),
      option_spec("--ratio", "R", o.target_ratio, "keep this fraction of the input faces, in (0, 1]"),
      option_spec("--max-error", "E", o.max_error,
                  "never collapse with error above E (RMS plane distance / bbox diagonal)"),
      choice_spec("--quadric-weights", "W", o.quadric_weights,
                  {{"area", QuadricWeights::area}, {"uniform", QuadricWeights::uniform}},
                  "area (a face's plane weighs its area) or uniform (1: CGAL GH's; lower Hausdorff, more image error on CAD)"),
      option_spec("--area-floor", "F", o.area_floor,
                  "area weights: a face weighs its area + F x the median face area (1: lower Hausdorff on scans, "
                  "less image error on CAD than uniform)"),
      option_spec("--boundary-weight", "W", o.boundary_weight,
                  "weight of boundary constraint planes, in faces (area weights: x edge length^2); 0 disables"),
      switch_spec("--freeze-boundary", o.freeze_boundary, "never move or remove boundary vertices"),
      option_spec("--max-normal-change", "DEG", o.max_normal_change_deg,
                  "reject collapses turning a face normal by more than DEG degrees, (0, 180]"),
      option_spec("--visibility-exponent", "P", o.visibility_exponent,
                  "VG: weight face quadrics by V^P in the queue order (2: Zhang & Turk eq. 5.10)"),
      switch_spec("--no-folds", o.prevent_folds,
                  "reject collapses that fold a face back onto its neighbour (thin plates keep their rims)"),
      switch_spec("--crease-visibility", o.crease_visibility,
                  "VG: a face meeting a more visible face at a crease (> 30 deg) takes its V"),
      switch_spec("--serial-collapses", o.serial_collapses,
                  "one collapse sequence, no parallel phase (what --targets/--levels run; equals their level)"),
  };
}

const char* to_string(StopReason reason) {
  switch (reason) {
    case StopReason::target_reached:
      return "target_reached";
    case StopReason::error_limit:
      return "error_limit";
    case StopReason::no_legal_collapse:
      return "no_legal_collapse";
    case StopReason::nothing_to_do:
      return "nothing_to_do";
  }
  return "?";
}

const char* to_string(QuadricWeights weights) { return weights == QuadricWeights::area ? "area" : "uniform"; }

namespace {

constexpr std::uint8_t kAlive = 1;
constexpr std::uint8_t kLocked = 2;    // never moved or removed; a free neighbour may collapse onto it
constexpr std::uint8_t kBoundary = 4;  // on an open boundary
constexpr std::uint8_t kRejected = 8;  // a collapse at this vertex was refused; retry after nearby changes
constexpr std::uint8_t kCut = 16;      // parallel phase: has a neighbour in another partition
constexpr std::uint32_t kNoFace = 0xffffffffu;  // no face has this index (faces are counted in 32 bits)

// A candidate in the queue (key: radix_key of its cost when costed at `time`). When an end
// changed after `time` the entry is dated: the lazy queue costs it again when it is popped,
// an eager one drops it (CollapseEngine::take_current).
// A CollapseCost refuses a collapse with an infinite cost (the walkthrough paper's projected
// length tolerance): the key sorts after every finite cost, and such entries are skipped like
// collapses over max_error until a neighbouring collapse re-costs the edge.
constexpr std::uint32_t kRefusedKey = 0x7f800000u;  // the bits of +infinity

struct HeapEntry {
  std::uint32_t key;
  VertexIndex v0, v1;
  std::uint32_t time;
};
using Entries = detail::LargeArray<HeapEntry>;  // the queues' edges: used to their end
// Edge arrays that grow, or are reserved from an estimate, and of which the parallel phase
// has one per partition (hundreds at 14M faces): never rounded up to a huge page.
using GrowingEntries = detail::GrowingArray<HeapEntry>;

/* Collapse profile of the edge (v0, v1); v1 is merged into v0 at `placement`.

            vl
           /  \
          / fl \
        v0 ---- v1
          \ fr /
           \  /
            vr

   fl, fr: the faces removed (only fl on a boundary edge); vl, vr: the opposite vertices. */
struct CollapseProfile {
  VertexIndex v0 = 0, v1 = 0;
  std::uint32_t removed[2] = {0, 0};
  VertexIndex opposite[2] = {0, 0};
  int num_removed = 0;
  Placement placement;
  double error = 0;  // RMS plane distance in the unit frame (= relative to the diagonal)
};

// A lane's queue. The serial loop's splits its keys by bytes (an entry moves at most three
// times before it is popped); a partition's by bits, whose fewer non-empty buckets hold fewer
// part-filled blocks over hundreds of partitions at 14M faces (radix_heap.h). Both pop in the
// same order, so which one a lane uses changes no result. The two are types of their own, each
// compiled for its digits: one class choosing at run time cost the partitions' queues a
// quarter more instructions (the dragon at 10%).
class Queue {
 public:
  void sort_by_bytes() { by_bytes_ = true; }  // before anything is queued
  bool empty() const { return by_bytes_ ? bytes_.empty() : bits_.empty(); }
  std::size_t size() const { return by_bytes_ ? bytes_.size() : bits_.size(); }
  void push(const HeapEntry& e) { by_bytes_ ? bytes_.push(e) : bits_.push(e); }
  HeapEntry pop() { return by_bytes_ ? bytes_.pop() : bits_.pop(); }
  std::uint32_t min_key() { return by_bytes_ ? bytes_.min_key() : bits_.min_key(); }
  bool pop_at_most(std::uint32_t limit, HeapEntry& out) {
    return by_bytes_ ? bytes_.pop_at_most(limit, out) : bits_.pop_at_most(limit, out);
  }
  void assign(Entries&& items) { by_bytes_ ? bytes_.assign(std::move(items)) : bits_.assign(std::move(items)); }
  template <class Items>
  void assign_spread(const Items& items) {
    by_bytes_ ? bytes_.assign_spread(items) : bits_.assign_spread(items);
  }
  void take_all(Entries& into) { by_bytes_ ? bytes_.take_all(into) : bits_.take_all(into); }
  template <class Pred>
  void remove_if(Pred drop) {
    by_bytes_ ? bytes_.remove_if(drop) : bits_.remove_if(drop);
  }

 private:
  detail::RadixHeap<HeapEntry, Entries, 1> bits_;
  detail::RadixHeap<HeapEntry, Entries, 8> bytes_;
  bool by_bytes_ = false;
};

struct MovedFace {
  std::uint32_t face;
  Vec3 n_old, n_new;  // unnormalised normals before and after the candidate collapse
};

// A queue with its clock, marks and scratch. The serial loop has one over every vertex; in
// the parallel phase each partition has its own, and a lane changes only its own vertices'
// state, so lanes run on different threads at once.
// A cache line of its own: lanes side by side run on different threads, and each writes its
// queue's buckets and tallies at every collapse.
struct alignas(64) Lane {
  Queue heap;
  std::uint32_t clock = 0;    // the lane's vertices' modified_ and requeued_, and its entries' times
  std::uint32_t mark_id = 0;  // the last mark given to one of its vertices
  VertexIndex first_vertex = 0, last_vertex = 0;
  std::vector<VertexIndex> ring, second_ring;
  std::vector<std::uint8_t> ring_had_edge;  // collapse(): per ring vertex, an edge with v0 before
  std::vector<MovedFace> moved_faces;
  bool error_limited = false;
  std::size_t compact_at = 0;      // the heap size the next compaction waits for (maybe_compact_heap)
  std::size_t requeued_edges = 0;  // edges costed after the set-up (SimplifyResult::requeued_edges)
  // Partitions only.
  bool partition = false;
  bool done = false;                   // reached its face budget
  GrowingEntries leftover;  // edges for the serial phase: crossing, or not deep
  std::size_t faces_at_start = 0, faces_removed = 0, face_budget = 0;
  SimplifyResult tally;                // its collapses, refusals and largest error
};

// The parallel phase (docs/simplify.md, "Two cores"). Partitions are runs of this many
// consecutive vertices in the engine's spatial order: a fixed size, so the result does not
// depend on the thread count.
constexpr std::size_t kPartitionVertices = std::size_t(1) << 15;
// Vertices per job in the set-up's parallel loops (their results do not depend on it). Small
// enough that a mesh under one partition splits into even jobs: at 16,384 the D-sub
// connector's 47k vertices were 3 jobs (classify) or 2 partition-sized chunks of 32,768 and
// 14,196 (initial edges) for two threads.
constexpr std::size_t kSetupRange = std::size_t(1) << 12;
// Threads for a set-up loop of `ranges` such jobs: one more thread only for two jobs or more
// each. Starting a thread (and waking the core it runs on) costs about as much as a job here:
// fandisk's 6.5k vertices, two jobs, set up in 4.5-4.8 ms on one thread against 5.1-5.6 ms on
// two (first calls, ten alternating pairs); the aneurysm's three jobs came out even, the cap's
// seven and the D-sub's twelve are faster on two. Results do not depend on it.
unsigned setup_workers(unsigned workers, std::size_t ranges) { return worker_count(workers, ranges / 2); }
// How deep the phase goes, a ladder fixed in advance so that a run's phase depends only on
// which rung its target is under. At depth d a partition stops once it has removed
// budget_per_mille/1000 of its faces, so the phase never ends below (1000 - budget)/1000 of
// the input and every target at or below that shares it; rounds stop once `goal` of the
// faces is left. Depth 1 serves targets from 30% down, depth 2 those from 12%, depth 3 those
// at 5% and below. Without depth 2 a run to 10% did the phase to 35% and the rest, a quarter
// of the input's collapses, on one thread (docs/simplify.md, "Three rungs").
struct PhaseRung {
  std::size_t budget_per_mille;
  double goal;
  // The goal counts only the faces the phase can remove (no cut vertex): the cut band stays
  // at full resolution, and a deep goal over all faces would crush the interiors to meet it.
  bool goal_of_interior;
};
constexpr PhaseRung kPhaseRungs[] = {{700, 0.35, false}, {880, 0.17, true}, {950, 0.07, true}};
constexpr int kDeepestPhase = static_cast<int>(std::size(kPhaseRungs));
// parallel_phase_depth takes the deepest rung a target is under: budgets must grow with depth.
static_assert(kPhaseRungs[0].budget_per_mille < kPhaseRungs[1].budget_per_mille &&
              kPhaseRungs[1].budget_per_mille < kPhaseRungs[2].budget_per_mille);
// Each round's cost threshold is the last one's float bits plus half a binade (x1.33-1.5).
constexpr std::uint32_t kThresholdStep = std::uint32_t(1) << 22;
constexpr std::uint32_t kLastFiniteKey = 0x7f7fffffu;

// Hands the pages of freed blocks back to the system. The phase's queues grow and shrink on
// every worker's malloc arena, and glibc keeps what they free: at 14M faces that was 800 MB of
// resident memory no one used (peak 202 -> 186 B per input face with this after every round).
// Pages given back are faulted in again when the queues regrow, so a trim pays only when much
// is held: below kTrimFloor it is skipped. On the dragon (free 4-52 MB at each call) the trims
// cost 14% of the run in page faults; at 14M faces (median 300 MB held) nearly all still run.
constexpr std::size_t kTrimFloor = std::size_t(16) << 20;

void give_back_freed_memory() {
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
  if (mallinfo2().fordblks >= kTrimFloor) malloc_trim(0);
#elif defined(__GLIBC__)
  malloc_trim(0);  // no mallinfo2 before glibc 2.33: trim every time, as before the floor
#endif
}

// `yes` when `condition`, else `no`, by a mask: GCC turned the ternary operator into a branch in
// the loops below, whose conditions are data the branch predictor cannot learn.
inline std::uint32_t select_if(bool condition, std::uint32_t yes, std::uint32_t no) {
  const std::uint32_t mask = 0u - static_cast<std::uint32_t>(condition);
  return (yes & mask) | (no & ~mask);
}

// Bitwise, not short-circuit: which corner holds v is data the branch predictor cannot learn.
// (On ints: clang's -Wbitwise-instead-of-logical takes `|` between bools for a slip.)
bool has_vertex(const Face& f, VertexIndex v) { return (int(f[0] == v) | int(f[1] == v) | int(f[2] == v)) != 0; }

// The corner of f that is neither a nor b, for a face that holds both (the engine's faces have
// three distinct corners): by exclusive or, not by branches on which corner it is.
VertexIndex third_vertex(const Face& f, VertexIndex a, VertexIndex b) { return f[0] ^ f[1] ^ f[2] ^ a ^ b; }

class CollapseEngine {
 public:
  // `phase_depth` > 0: set up the parallel phase of that rung (run_parallel_phase); `workers`
  // threads build the queue either way.
  // `owned`, when given, is `input` itself, given up by the caller (simplify(Mesh&&)).
  CollapseEngine(const Mesh& input, const SimplifyOptions& options, int phase_depth, unsigned workers,
                 Mesh* owned = nullptr)
      : input_(input),
        frame_(unit_frame(bounding_box(input))),
        cos_max_normal_change_(std::cos(options.max_normal_change_deg * M_PI / 180.0)),
        prevent_folds_(options.prevent_folds),
        input_faces_(input.num_faces()),
        area_weights_(options.quadric_weights == QuadricWeights::area),
        area_floor_factor_(options.area_floor),
        boundary_weight_(options.boundary_weight) {
    const std::size_t nv = input.num_vertices();
    reorder_spatially(input, workers);
    positions_.resize(nv);
    parallel_ranges(nv, kSetupRange, setup_workers(workers, (nv + kSetupRange - 1) / kSetupRange), [&](std::size_t begin, std::size_t end) {
      for (std::size_t v = begin; v < end; ++v) positions_[v] = frame_.to_unit(input.positions[input_vertex_[v]]);
    });
    face_alive_.assign(faces_.size(), 1);
    faces_alive_ = faces_.size();
    // A face with a repeated index is a segment or a point: no area, no plane, no place in a
    // fan. Dropping it first keeps it from locking its vertices (junk exporters emit
    // thousands); nothing that had area or connectivity is lost.
    for (std::size_t f = 0; f < faces_.size(); ++f) {
      const Face& face = faces_[f];
      if (face[0] == face[1] || face[1] == face[2] || face[0] == face[2]) {
        face_alive_[f] = 0;
        --faces_alive_;
        ++dropped_repeated_index_faces_;
      }
    }
    flags_.assign(nv, kAlive);
    modified_.assign(nv, 0);
    requeued_.assign(nv, 0);
    mark_.assign(nv, 0);
    origin_.assign(input_vertex_.begin(), input_vertex_.end());
    weighted_ = options.method == SimplifyMethod::vg;
    custom_cost_ = options.collapse_cost;
    lazy_ = custom_cost_ == nullptr;
    if (custom_cost_ != nullptr && !options.vertex_weights.empty()) {
      vertex_weights_.resize(nv);
      for (std::size_t v = 0; v < nv; ++v) vertex_weights_[v] = options.vertex_weights[input_vertex_[v]];
    }
    if (weighted_)
      weighted_quadrics_.assign(nv, VertexQuadrics{});
    else
      quadrics_.assign(nv, Quadric{});
    build_vertex_faces();
    if (weighted_) compute_face_weights(options);
    classify_vertices(options, workers);
    add_face_quadrics();
    serial_.last_vertex = static_cast<VertexIndex>(nv);
    serial_.heap.sort_by_bytes();
    phase_depth_ = phase_depth;
    // From here on the engine reads only the input's positions and qualities: a given-up
    // input shrinks before the queue is costed, the set-up's largest allocation.
    if (owned != nullptr) {
      std::vector<Face>().swap(owned->faces);
      keep_input_positions_as_floats(*owned);
    }
    push_initial_edges(phase_depth > 0, workers);
  }

  // Collapses in queue order while more than `target` faces remain. A legal collapse that
  // would end one face below the target is deferred (a closed mesh cannot hit an odd target;
  // a boundary collapse elsewhere may still hit it exactly). With stop_at_deferral the loop
  // returns at the first deferral (simplify_levels finishes that level on a copy); otherwise
  // it runs on and then tries the deferred entries. `first`, when set, is taken before the
  // queue: the entry a previous level stopped at.
  void run(std::size_t target, double max_error, SimplifyResult& result, std::vector<HeapEntry>& deferred,
           bool stop_at_deferral, const HeapEntry* first = nullptr) {
    Lane& lane = serial_;
    struct CountRequeued {  // on every return: this run's share of the lane's count
      SimplifyResult& result;
      const std::size_t& count;
      std::size_t before;
      ~CountRequeued() { result.requeued_edges += count - before; }
    } count_requeued{result, lane.requeued_edges, lane.requeued_edges};
    while ((first != nullptr || !lane.heap.empty()) && faces_alive_ > target) {
      // Once a collapse is deferred, one face above the target, only a collapse that removes
      // one face (of an edge with one face, whose ends both carry kBoundary: classify flags
      // them, a collapse ORs v1's flag into v0, and an edge it merges keeps (a-1)+(b-1) >= 2
      // faces unless a side already had one) can still be performed; until it is, none is,
      // so the deferred entry stays legal. Skipping the rest changes nothing; on a closed
      // mesh nothing is left to find, and the queue is left as it is. (Scanning the rest of the queue cost a
      // closed mesh a fifth of its serial loop: 122k entries prepared and tested on the
      // dragon at 10%.)
      if (!deferred.empty() && !has_boundary_) break;
      const HeapEntry entry = first != nullptr ? *first : lane.heap.pop();
      first = nullptr;
      if (!deferred.empty() && !(flags_[entry.v0] & flags_[entry.v1] & kBoundary)) continue;
      CollapseProfile profile;
      HeapEntry current = entry;
      if (!take_current(lane, current) || !prepare(current, profile)) continue;
      if (profile.error > max_error || (custom_cost_ != nullptr && current.key == kRefusedKey)) {
        lane.error_limited = true;
        if (lazy_) set_aside(profile);
        continue;
      }
      if (!legal(lane, profile)) {
        ++result.rejected_collapses;
        set_aside(profile);
        continue;
      }
      if (faces_alive_ - static_cast<std::size_t>(profile.num_removed) < target) {
        deferred.push_back(current);
        if (stop_at_deferral) return;
        continue;
      }
      collapse(lane, profile, result);
      report_progress();
      maybe_compact_heap(lane);
    }
    if (stop_at_deferral) return;
    for (const HeapEntry& entry : deferred) {
      if (faces_alive_ <= target) break;
      CollapseProfile profile;
      if (!is_obsolete(entry) && prepare(entry, profile) && profile.error <= max_error && legal(lane, profile))
        collapse(lane, profile, result);
    }
    if (faces_alive_ <= target)
      result.stop_reason = result.collapses ? StopReason::target_reached : StopReason::nothing_to_do;
    else
      result.stop_reason = lane.error_limited ? StopReason::error_limit : StopReason::no_legal_collapse;
  }

  std::size_t faces_alive() const { return faces_alive_; }

  // The parallel phase: rounds in which every partition collapses, in its own queue's order,
  // the deep edges (is_deep) that cost at most the round's threshold, until the faces are
  // down to the rung's goal of the start (or every partition has used its budget). Partitions
  // change no vertex, face or list memory that another reads, so they may run on any threads
  // in any order with the same result. Then every queue and the edges left over become one
  // queue, and run() goes on from there serially. Needs an engine built with a phase depth.
  void run_parallel_phase(double max_error, unsigned workers, SimplifyResult& result) {
    const std::size_t start = faces_alive_;
    const PhaseRung& rung = kPhaseRungs[phase_depth_ - 1];
    std::size_t counted = start;  // the faces the goal is a fraction of
    if (rung.goal_of_interior) {
      counted = 0;
      for (std::size_t f = 0; f < faces_.size(); ++f)
        counted += face_alive_[f] && !((flags_[faces_[f][0]] | flags_[faces_[f][1]] | flags_[faces_[f][2]]) & kCut);
    }
    const std::size_t goal_removed = counted - static_cast<std::size_t>(rung.goal * double(counted));
    vertex_faces_.split_into_regions(kPartitionVertices, 0.25);
    workers = worker_count(workers, lanes_.size());
    std::uint32_t threshold = first_threshold_;
    for (;;) {
      parallel_for(0, lanes_.size(), workers,
                   [&](unsigned, std::size_t i) {
                     run_partition(lanes_[i], threshold, max_error);
                     if (i % 16 == 15) give_back_freed_memory();
                   });
      std::size_t removed = 0;
      std::uint32_t lowest_left = UINT32_MAX;  // the smallest key still queued
      for (Lane& lane : lanes_) {
        removed += lane.faces_removed;
        if (!lane.done && !lane.heap.empty()) lowest_left = std::min(lowest_left, lane.heap.min_key());
      }
      faces_alive_ = start - removed;
      report_progress();
      give_back_freed_memory();
      if (removed >= goal_removed || lowest_left > kLastFiniteKey || threshold >= kLastFiniteKey) break;
      // The next threshold, skipping rounds in which nothing would be collapsed.
      threshold = std::max(lowest_left, threshold > kLastFiniteKey - kThresholdStep ? kLastFiniteKey
                                                                                     : threshold + kThresholdStep);
    }
    join_partitions(result);
  }

  bool has_boundary() const { return has_boundary_; }

  void set_observer(SimplifyObserver* observer, std::size_t final_target) {
    observer_ = observer;
    planned_ = faces_alive_ > final_target ? faces_alive_ - final_target : 0;
    report_every_ = std::max<std::size_t>(1, planned_ / 100);
    next_report_ = faces_alive_ - std::min(faces_alive_, report_every_);
  }

  // The mesh left, in the input's order: surviving vertices and faces in the order of their
  // input indices (the engine's spatial order stays inside).
  Mesh extract() const {
    Mesh out;
    const std::size_t nv = input_vertex_.size();
    std::vector<VertexIndex> engine_index(nv);
    for (std::size_t v = 0; v < nv; ++v) engine_index[input_vertex_[v]] = static_cast<VertexIndex>(v);
    std::vector<VertexIndex> remap(nv, 0);  // engine vertex -> output vertex
    for (std::size_t i = 0; i < nv; ++i) {
      const VertexIndex v = engine_index[i];
      if (!(flags_[v] & kAlive)) continue;
      remap[v] = static_cast<VertexIndex>(out.positions.size());
      out.positions.push_back(origin_[v] != kNoOrigin ? input_position(origin_[v]) : frame_.from_unit(positions_[v]));
      if (input_.has_vertex_quality()) out.vertex_quality.push_back(input_.vertex_quality[i]);
    }
    std::vector<VertexIndex>().swap(engine_index);
    std::vector<std::uint32_t> engine_face(faces_.size());
    for (std::size_t f = 0; f < faces_.size(); ++f) engine_face[input_face_[f]] = static_cast<std::uint32_t>(f);
    out.faces.reserve(faces_alive_);
    for (std::size_t i = 0; i < faces_.size(); ++i) {
      const std::uint32_t f = engine_face[i];
      if (!face_alive_[f]) continue;
      out.faces.push_back({remap[faces_[f][0]], remap[faces_[f][1]], remap[faces_[f][2]]});
      if (input_.has_face_quality()) out.face_quality.push_back(input_.face_quality[i]);
    }
    return out;
  }

  std::size_t dropped_repeated_index_faces() const { return dropped_repeated_index_faces_; }

  // For a caller that gives its mesh up (simplify(Mesh&&)): when every input coordinate is a
  // float, as PLY, STL and most OBJ files hold them, the engine keeps them as floats (exact,
  // half the bytes) for extract() and frees the caller's doubles: 84 MB at 14M faces.
  void keep_input_positions_as_floats(Mesh& owned) {
    auto is_float = [](double x) { return static_cast<double>(static_cast<float>(x)) == x; };
    for (const Vec3& p : owned.positions)
      if (!is_float(p.x) || !is_float(p.y) || !is_float(p.z)) return;
    input_positions_float_.resize(owned.positions.size());
    for (std::size_t i = 0; i < owned.positions.size(); ++i) {
      const Vec3& p = owned.positions[i];
      input_positions_float_[i] = {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
    }
    std::vector<Vec3>().swap(owned.positions);
  }

  std::size_t locked_vertices() const {
    return static_cast<std::size_t>(
        std::count_if(flags_.begin(), flags_.end(), [](std::uint8_t f) { return f & kLocked; }));
  }

 private:
  // Engine order: vertices along a Morton curve, faces by their first vertex in that order
  // (a counting sort, stable in input order). Neighbours then sit close in every per-vertex
  // and per-face array: on meshes whose input order has little locality (a subdivided or
  // merged mesh) the collapse loop otherwise waits on memory.
  void reorder_spatially(const Mesh& input, unsigned workers) {
    const std::size_t nv = input.num_vertices(), nf = input.num_faces();
    input_vertex_ = spatial_vertex_order(input, workers);
    std::vector<VertexIndex> engine_index(nv);
    for (std::size_t v = 0; v < nv; ++v) engine_index[input_vertex_[v]] = static_cast<VertexIndex>(v);
    std::vector<std::uint32_t> first(nv + 1, 0);
    auto lowest = [&](const Face& f) { return std::min({engine_index[f[0]], engine_index[f[1]], engine_index[f[2]]}); };
    for (const Face& f : input.faces) ++first[lowest(f) + 1];
    for (std::size_t v = 0; v < nv; ++v) first[v + 1] += first[v];
    input_face_.resize(nf);
    faces_.resize(nf);
    for (std::size_t i = 0; i < nf; ++i) {
      const Face& f = input.faces[i];
      const std::uint32_t slot = first[lowest(f)]++;
      input_face_[slot] = static_cast<std::uint32_t>(i);
      faces_[slot] = {engine_index[f[0]], engine_index[f[1]], engine_index[f[2]]};
    }
  }

  void build_vertex_faces() {
    vertex_faces_.build(positions_.size(), faces_, [&](std::size_t f) { return !face_alive_[f]; });
  }

  // VG: V(t)^P per input face; with crease_visibility, V(t) is first raised to the V of any
  // face across an edge where the normals differ by more than 30°.
  void compute_face_weights(const SimplifyOptions& options) {
    constexpr double kCreaseCosine = 0.8660254037844387;  // cos 30°
    const std::vector<float>& input_visibility = options.face_visibility;
    auto visibility = [&](std::size_t f) { return input_visibility[input_face_[f]]; };
    input_visibility_ = &input_visibility;
    if (!options.crease_visibility && options.visibility_exponent == 2.0) return;  // face_weight squares V
    face_weight_.resize(faces_.size());
    for (std::size_t f = 0; f < faces_.size(); ++f) {
      double v = visibility(f);
      if (options.crease_visibility && face_alive_[f]) {
        const Face& face = faces_[f];
        const Vec3 n = unit_normal(face);
        for (int k = 0; k < 3; ++k) {
          const VertexIndex a = face[k], b = face[(k + 1) % 3];
          for (std::uint32_t g : vertex_faces_[a])
            if (visibility(g) > v && has_vertex(faces_[g], b) && dot(n, unit_normal(faces_[g])) < kCreaseCosine)
              v = visibility(g);
        }
      }
      face_weight_[f] = options.visibility_exponent == 2.0 ? v * v : std::pow(v, options.visibility_exponent);
    }
  }

  // VG: V(t)^P of engine face f. The default (P = 2, no crease visibility) squares the
  // input's V where a plane is added, with no array of its own; otherwise
  // compute_face_weights filled face_weight_.
  double face_weight(std::size_t f) const {
    if (!face_weight_.empty()) return face_weight_[f];
    const double v = (*input_visibility_)[input_face_[f]];
    return v * v;
  }

  Vec3 unit_normal(const Face& f) const {
    const Vec3 n = cross(positions_[f[1]] - positions_[f[0]], positions_[f[2]] - positions_[f[0]]);
    const double len = norm(n);
    return len > 0 ? n / len : Vec3{};
  }

  struct BoundaryEdge {
    std::uint32_t face;
    VertexIndex a, b;
  };

  // Locks vertices the collapse rules cannot handle (edges with 3+ faces, misoriented
  // edges, several fans, a frozen boundary) and adds boundary planes. Ranges of vertices are
  // classified in parallel (each writes only its own vertices' flags); the boundary edges
  // they find are planed afterwards in vertex order, so every quadric sums the same planes in
  // the same order for any thread count.
  void classify_vertices(const SimplifyOptions& options, unsigned workers) {
    const std::size_t nv = positions_.size(), ranges = (nv + kSetupRange - 1) / kSetupRange;
    std::vector<std::vector<BoundaryEdge>> boundary_edges(ranges);
    parallel_ranges(nv, kSetupRange, setup_workers(workers, ranges), [&](std::size_t begin, std::size_t end) {
      classify_range(static_cast<VertexIndex>(begin), static_cast<VertexIndex>(end), options,
                     boundary_edges[begin / kSetupRange]);
    });
    for (const std::vector<BoundaryEdge>& edges : boundary_edges) {
      has_boundary_ = has_boundary_ || !edges.empty();
      for (const BoundaryEdge& e : edges) add_boundary_plane(e.face, e.a, e.b);
    }
  }

  void classify_range(VertexIndex begin, VertexIndex end, const SimplifyOptions& options,
                      std::vector<BoundaryEdge>& boundary_edges) {
    struct Incidence {
      VertexIndex other;
      bool outgoing;        // the face runs v -> other
      std::uint32_t local;  // index of the face in vertex_faces_[v]
      bool operator<(const Incidence& o) const { return other < o.other || (other == o.other && local < o.local); }
    };
    std::vector<Incidence> inc;
    UnionFind fans;
    for (VertexIndex v = begin; v < end; ++v) {
      const auto& vf = vertex_faces_[v];
      if (vf.empty() || (flags_[v] & kLocked)) continue;
      if (is_closed_fan(v, vf)) continue;  // the usual vertex: no flag to set
      inc.clear();
      for (std::uint32_t i = 0; i < vf.size(); ++i) {
        const Face& f = faces_[vf[i]];
        const int k = f[0] == v ? 0 : (f[1] == v ? 1 : 2);
        inc.push_back({f[(k + 1) % 3], true, i});
        inc.push_back({f[(k + 2) % 3], false, i});
      }
      std::sort(inc.begin(), inc.end());
      fans.reset(vf.size());
      std::size_t fan_count = vf.size();
      bool locked = false, boundary = false;
      for (std::size_t i = 0; i < inc.size();) {
        std::size_t j = i;
        while (j < inc.size() && inc[j].other == inc[i].other) ++j;
        const std::size_t count = j - i;
        if (count > 2)
          locked = true;  // non-manifold edge
        else if (count == 2) {
          if (inc[i].outgoing == inc[i + 1].outgoing)
            locked = true;  // misoriented neighbours
          else if (fans.unite(inc[i].local, inc[i + 1].local))
            --fan_count;
        } else {
          boundary = true;
          if (v < inc[i].other) boundary_edges.push_back({vf[inc[i].local], v, inc[i].other});
        }
        i = j;
      }
      if (fan_count > 1) locked = true;  // several fans meet at v
      if (boundary) flags_[v] |= kBoundary;
      if (locked || (boundary && options.freeze_boundary)) flags_[v] |= kLocked;
    }
  }

  // True when v's faces (at most kClosedFanFaces of them) form one closed fan of manifold,
  // consistently oriented edges: each face's next vertex after v is the previous vertex of
  // exactly one face, and following next -> previous from the first face visits all of them
  // once. Then every neighbour is on two faces that run it in opposite directions and the
  // fans are one: classify_range's general test, which sorts v's incidences, would set no
  // flag. (That sort and a union-find per vertex were 8% of the D-sub's instructions.)
  static constexpr std::size_t kClosedFanFaces = 16;
  bool is_closed_fan(VertexIndex v, const detail::VertexFaceLists::Range& vf) const {
    const std::size_t k = vf.size();
    if (k < 3 || k > kClosedFanFaces) return false;
    VertexIndex next[kClosedFanFaces], previous[kClosedFanFaces];
    for (std::size_t i = 0; i < k; ++i) {
      const Face& f = faces_[vf[i]];
      const int c = (f[1] == v) + 2 * (f[2] == v);  // v's corner, without branches
      next[i] = f[(c + 1) % 3];
      previous[i] = f[(c + 2) % 3];
    }
    std::uint8_t successor[kClosedFanFaces];
    for (std::size_t i = 0; i < k; ++i) {
      // Every j is compared (selects, not branches): none is a boundary edge, two or more an
      // edge on three or more faces, or misoriented.
      int found = 0, matches = 0;
      for (std::size_t j = 0; j < k; ++j) {
        const bool match = previous[j] == next[i];
        matches += match;
        found = static_cast<int>(select_if(match, std::uint32_t(j), std::uint32_t(found)));
      }
      if (matches != 1) return false;
      successor[i] = static_cast<std::uint8_t>(found);
    }
    std::size_t at = 0;
    for (std::size_t steps = 1; steps <= k; ++steps) {
      at = successor[at];
      if (at == 0) return steps == k;  // back at the first face: one fan iff every face was visited
    }
    return false;  // a cycle that misses the first face: several fans
  }

  // The plane through boundary edge (a, b) perpendicular to its face, weighing
  // boundary_weight faces: an area-weighted face weighs ~|e|², a uniform one 1.
  void add_boundary_plane(std::uint32_t face, VertexIndex a, VertexIndex b) {
    if (boundary_weight_ <= 0) return;
    const Face& f = faces_[face];
    const Vec3 n = cross(positions_[f[1]] - positions_[f[0]], positions_[f[2]] - positions_[f[0]]);
    const Vec3 e = positions_[b] - positions_[a];
    const Vec3 m = cross(e, n);
    const double len = norm(m);
    if (!(len > 0) || is_degenerate_in_unit_frame(f)) return;
    const double weight = area_weights_ ? boundary_weight_ * squared_norm(e) : boundary_weight_;
    Quadric q = Quadric::plane(m / len, positions_[a], weight);
    q.area = 0;  // constraint planes carry no surface area
    plain_quadric(a) += q;
    plain_quadric(b) += q;
    if (weighted_) {  // a boundary weighs what its face weighs
      const CostQuadric weighted = CostQuadric::from(q * face_weight(face));
      cost_quadric(a) += weighted;
      cost_quadric(b) += weighted;
    }
  }

  bool is_degenerate_in_unit_frame(const Face& f) const {
    return is_degenerate_triangle(positions_[f[0]], positions_[f[1]], positions_[f[2]]);
  }

  // Each face's plane quadric (weight 1, or its area) goes to its three vertices; the
  // quadric's `area` is that weight, so an error / area is a mean squared distance either way.
  // Under VG also V(t)² times it goes to
  // the cost quadrics. Collapses add quadrics, so a vertex always carries the weighted planes
  // of every input face merged into it: weights follow the input faces, never the current ones.
  void add_face_quadrics() {
    const double floor = area_weights_ && area_floor_factor_ > 0 ? area_floor_factor_ * median_face_area() : 0.0;
    for (std::size_t i = 0; i < faces_.size(); ++i) {
      const Face& f = faces_[i];
      const Vec3 n = cross(positions_[f[1]] - positions_[f[0]], positions_[f[2]] - positions_[f[0]]);
      const double len = norm(n);
      if (!adds_plane(f, len)) continue;
      const Quadric q = Quadric::plane(n / len, positions_[f[0]], area_weights_ ? 0.5 * len + floor : 1.0);
      add_quadric(i, f, q);
    }
  }

  // A face with a repeated index or no area adds no plane (and no area to the floor's median).
  bool adds_plane(const Face& f) const {
    return adds_plane(f, norm(cross(positions_[f[1]] - positions_[f[0]], positions_[f[2]] - positions_[f[0]])));
  }
  // The same for a caller that has the face's |cross| (twice its area) already.
  bool adds_plane(const Face& f, double cross_length) const {
    return f[0] != f[1] && f[1] != f[2] && f[0] != f[2] &&
           !is_degenerate_triangle(positions_[f[0]], positions_[f[1]], positions_[f[2]], cross_length);
  }

  // The median area (unit frame) of the faces that add a plane, 0 when none does. Floats: the
  // 14M-face mesh's set-up would otherwise hold 8 more bytes per face; the floor needs no
  // more than float precision.
  double median_face_area() const {
    std::vector<float> areas;
    areas.reserve(faces_.size());
    for (const Face& f : faces_) {
      if (!adds_plane(f)) continue;
      areas.push_back(static_cast<float>(0.5 * norm(cross(positions_[f[1]] - positions_[f[0]], positions_[f[2]] - positions_[f[0]]))));
    }
    if (areas.empty()) return 0.0;
    const auto middle = areas.begin() + static_cast<std::ptrdiff_t>(areas.size() / 2);
    std::nth_element(areas.begin(), middle, areas.end());
    return *middle;
  }

  void add_quadric(std::size_t face, const Face& f, const Quadric& q) {
    for (VertexIndex v : f) plain_quadric(v) += q;
    if (weighted_) {
      const CostQuadric weighted = CostQuadric::from(q * face_weight(face));
      for (VertexIndex v : f) cost_quadric(v) += weighted;
    }
  }

  // A mark value no vertex carries yet (marks replace per-call sets of visited vertices).
  // A lane marks only its own vertices, so on wrapping it clears only those.
  std::uint32_t fresh_mark(Lane& lane) {
    if (lane.mark_id == UINT32_MAX) {
      std::fill(mark_.begin() + lane.first_vertex, mark_.begin() + lane.last_vertex, 0);
      lane.mark_id = 0;
    }
    return ++lane.mark_id;
  }

  template <class Fn>
  void for_each_neighbor(Lane& lane, VertexIndex v, Fn&& fn) {
    visit_neighbors(mark_, fresh_mark(lane), v, fn);
  }

  // Calls fn once for every vertex that shares a face with v, marking v and them with `id`
  // in `mark` (a mark newer than any it holds).
  template <class Marks, class Fn>
  void visit_neighbors(Marks& mark, std::uint32_t id, VertexIndex v, Fn&& fn) const {
    mark[v] = id;
    for (std::uint32_t f : vertex_faces_[v])
      for (VertexIndex w : faces_[f])
        if (mark[w] != id) {
          mark[w] = id;
          fn(w);
        }
  }

  // visit_neighbors with nothing to call: every corner is stored without asking whether it was
  // seen (that test was a sixth of the D-sub's mispredicted branches at 1% in callgrind's
  // branch simulation).
  void mark_neighbors(std::uint32_t id, VertexIndex v) {
    mark_[v] = id;
    for (std::uint32_t f : vertex_faces_[v])
      for (VertexIndex w : faces_[f]) mark_[w] = id;
  }

  // Every edge once, costed into arrays that become the queues: one exactly sized for the
  // serial engine; when partitioned, one per partition, with the edges that cross into another
  // partition set aside for the serial phase. Chunks of vertices (a partition each, or
  // kSetupRange for the serial engine) are costed by `workers` threads, each into its own
  // slice, so the arrays (and so the ties in the queue) are the same for any thread count, and
  // in the order one thread would push them.
  void push_initial_edges(bool partitioned, unsigned workers) {
    const std::size_t nv = positions_.size();
    const std::size_t chunk_vertices = partitioned ? kPartitionVertices : kSetupRange;
    const std::size_t chunks = (nv + chunk_vertices - 1) / chunk_vertices;
    if (custom_cost_ != nullptr) workers = 1;  // a caller's cost need not be thread-safe
    workers = partitioned ? worker_count(workers, chunks) : setup_workers(workers, chunks);
    auto chunk_of = [&](VertexIndex v) { return std::size_t(v) / chunk_vertices; };
    auto chunk_end = [&](std::size_t c) { return static_cast<VertexIndex>(std::min(nv, (c + 1) * chunk_vertices)); };
    auto both_locked = [&](VertexIndex a, VertexIndex b) { return (flags_[a] & kLocked) && (flags_[b] & kLocked); };
    // Each thread its own marks: two threads may visit the same vertex. A cache line each: the
    // id is written at every vertex, and ids side by side made the two threads' edge costing
    // slower than one thread's (the D-sub's 11 ms set-up stage: 12.2 ms on two threads).
    struct alignas(64) WorkerMarks {
      std::vector<std::uint32_t> mark;
      std::uint32_t id = 0;
    };
    std::vector<WorkerMarks> marks(workers);
    auto neighbors = [&](unsigned worker, VertexIndex v, auto&& fn) {
      WorkerMarks& m = marks[worker];
      if (m.mark.empty() || m.id == UINT32_MAX) {
        m.mark.assign(nv, 0);
        m.id = 0;
      }
      visit_neighbors(m.mark, ++m.id, v, fn);
    };
    if (partitioned) {
      parallel_for(0, chunks, workers, [&](unsigned, std::size_t c) {
        for (VertexIndex v = static_cast<VertexIndex>(c * chunk_vertices); v < chunk_end(c); ++v)
          for (std::uint32_t f : vertex_faces_[v])
            for (VertexIndex w : faces_[f])
              if (chunk_of(w) != c) flags_[v] |= kCut;
      });
    }
    Entries serial_edges;
    std::vector<GrowingEntries> partition_edges;
    std::vector<std::vector<std::uint32_t>> samples(chunks);  // every 16th key, for the first round's threshold
    std::vector<std::size_t> offset(chunks + 1, 0);
    if (partitioned) {
      // No counting pass: a partition reserves room for as many edges as its vertices have
      // face incidences (twice a closed manifold's edge count, an estimate, never a limit).
      // The room never written is never faulted in, so it costs address space, not memory.
      lanes_.resize(chunks);
      partition_edges.resize(chunks);
    } else {
      // One array for the whole queue, each chunk's slice in place: counted first.
      std::vector<std::size_t> inner(chunks, 0);
      parallel_for(0, chunks, workers, [&](unsigned worker, std::size_t c) {
        std::size_t count = 0;  // not inner[c]: neighbouring counts share a cache line across threads
        for (VertexIndex v = static_cast<VertexIndex>(c * chunk_vertices); v < chunk_end(c); ++v)
          neighbors(worker, v, [&](VertexIndex w) { count += w > v && !both_locked(v, w); });
        inner[c] = count;
      });
      for (std::size_t c = 0; c < chunks; ++c) offset[c + 1] = offset[c] + inner[c];
      serial_edges.resize(offset[chunks]);
    }
    parallel_for(0, chunks, workers, [&](unsigned worker, std::size_t c) {
      if (partitioned) {
        std::size_t incidences = 0;
        for (VertexIndex v = static_cast<VertexIndex>(c * chunk_vertices); v < chunk_end(c); ++v)
          incidences += vertex_faces_[v].size();
        partition_edges[c].reserve(incidences);
      }
      HeapEntry* out = partitioned ? nullptr : serial_edges.data() + offset[c];
      for (VertexIndex v = static_cast<VertexIndex>(c * chunk_vertices); v < chunk_end(c); ++v)
        neighbors(worker, v, [&](VertexIndex w) {
          if (w <= v || both_locked(v, w)) return;
          const HeapEntry e = *edge_entry(v, w, 0);
          if (!partitioned)
            *out++ = e;
          else if (chunk_of(w) != c)
            lanes_[c].leftover.push_back(e);
          else
            partition_edges[c].push_back(e);
        });
      if (partitioned) {
        // Its queue now, and the array freed: all of them at once were the 14M-face set-up's peak.
        for (std::size_t i = 0; i < partition_edges[c].size(); i += 16) samples[c].push_back(partition_edges[c][i].key);
        lanes_[c].heap.assign_spread(partition_edges[c]);
        GrowingEntries().swap(partition_edges[c]);
      }
    });
    if (!partitioned) {
      serial_.heap.assign(std::move(serial_edges));
      return;
    }
    // Per partition: its vertex range, and how many faces it may remove (its faces are those
    // whose lowest vertex it owns: contiguous, faces being sorted by their lowest vertex).
    std::vector<std::size_t> faces_of(chunks, 0);
    for (std::size_t f = 0; f < faces_.size(); ++f)
      if (face_alive_[f]) ++faces_of[chunk_of(std::min({faces_[f][0], faces_[f][1], faces_[f][2]}))];
    std::vector<std::uint32_t> sample;
    for (std::size_t c = 0; c < chunks; ++c) {
      Lane& lane = lanes_[c];
      lane.partition = true;
      lane.first_vertex = static_cast<VertexIndex>(c * chunk_vertices);
      lane.last_vertex = chunk_end(c);
      lane.faces_at_start = faces_of[c];
      lane.face_budget = faces_of[c] * kPhaseRungs[phase_depth_ - 1].budget_per_mille / 1000;
      sample.insert(sample.end(), samples[c].begin(), samples[c].end());
    }
    if (!sample.empty()) {
      auto at = sample.begin() + static_cast<std::ptrdiff_t>(sample.size() / 20);
      std::nth_element(sample.begin(), at, sample.end());
      first_threshold_ = *at;
    }
  }

  // Collapsing (v0, v1): placed with the plain quadric; error = RMS distance of the placement
  // to the merged planes. Needed when an entry is popped; a push needs only the key.
  void place_and_measure(VertexIndex v0, VertexIndex v1, CollapseProfile& p) const {
    const Quadric q = plain_quadric(v0) + plain_quadric(v1);
    p.placement = placement(v0, v1, q);
    p.error = std::sqrt(p.placement.error / std::max(q.area, 1e-300));
  }

  // Where v1 goes when merged into v0: place()'s point, or v0 itself when v0 is locked (a
  // half-edge collapse: the locked vertex and its non-manifold surroundings stay as they are).
  Placement placement(VertexIndex v0, VertexIndex v1, const Quadric& q) const {
    if (!(flags_[v0] & kLocked)) return place(q, positions_[v0], positions_[v1]);
    Placement onto_v0;
    onto_v0.position = positions_[v0];
    onto_v0.kind = PlacementKind::endpoint0;
    onto_v0.error = q.evaluate(onto_v0.position);
    return onto_v0;
  }

  // The queue key: the float bits of the cost, Q(x) under QB and Q_v(x) under VG (eq. 5.9),
  // at the placement x of the plain quadric. Under VG every collapse among faces no camera
  // saw costs exactly 0; instead of leaving their order to the heap, they are ordered by the
  // plain error, mapped into the keys of the subnormal floats — below every normal cost — so
  // hidden parts still lose their least important detail first. With V ≡ 1, Q_v = Q and
  // the keys are QB's.
  std::uint32_t queue_key(VertexIndex v0, VertexIndex v1, const Placement& placement) const {
    if (custom_cost_ != nullptr) return custom_key(v0, v1, placement);
    const double plain = placement.error;
    if (!weighted_) return detail::radix_key(static_cast<float>(plain));
    const double cost = CostQuadric::evaluate_aligned_sum(cost_quadric(v0), cost_quadric(v1), placement.position);
    if (cost > 0 || !(plain > 0)) return detail::radix_key(static_cast<float>(cost));
    // The float bits of the plain error without their 8 lowest bits: monotone, 2^-15
    // relative resolution at every scale, and at most 0x7f8000, below the first normal float.
    // (A linear map of the plain error gave every small error the same key, leaving hidden
    // parts to the heap's order and to many refused collapses.)
    return 1u + (detail::radix_key(static_cast<float>(plain)) >> 8);
  }

  // A CollapseCost's key: its cost at the plain placement, in mesh coordinates.
  std::uint32_t custom_key(VertexIndex v0, VertexIndex v1, const Placement& placement) const {
    CollapseCost::Edge e;
    e.v0 = input_vertex_[v0];  // the caller's indices
    e.v1 = input_vertex_[v1];
    e.p0 = frame_.from_unit(positions_[v0]);
    e.p1 = frame_.from_unit(positions_[v1]);
    e.placed = frame_.from_unit(placement.position);
    e.n0 = vertex_normal(v0);
    e.n1 = vertex_normal(v1);
    if (!vertex_weights_.empty()) {
      e.w0 = vertex_weights_[v0];
      e.w1 = vertex_weights_[v1];
    }
    const double cost = custom_cost_->cost(e);
    if (cost == std::numeric_limits<double>::infinity()) return kRefusedKey;  // the cost's own stop rule
    return detail::radix_key(static_cast<float>(cost > 0 ? cost : 0.0));  // NaN and negatives first, never lost
  }

  Vec3 vertex_normal(VertexIndex v) const {
    Vec3 n{0, 0, 0};
    for (std::uint32_t f : vertex_faces_[v]) {
      if (!face_alive_[f]) continue;
      const Face& t = faces_[f];
      n = n + cross(positions_[t[1]] - positions_[t[0]], positions_[t[2]] - positions_[t[0]]);
    }
    const double length = norm(n);
    return length > 0 ? n / length : Vec3{0, 0, 0};
  }

  // Queues the collapse of edge (a, b). Between two free vertices b merges into a; when one
  // end is locked the free one merges into it (v0 = the locked end), so non-manifold,
  // misoriented or frozen parts still take in their free neighbours instead of stopping the
  // run; an edge between two locked vertices never collapses. A free vertex has one fan and
  // only manifold, consistently oriented edges, so the edge itself is always manifold.
  void push_edge(Lane& lane, VertexIndex a, VertexIndex b) {
    ++lane.requeued_edges;
    if (const std::optional<HeapEntry> e = edge_entry(a, b, lane.clock)) lane.heap.push(*e);
  }

  std::optional<HeapEntry> edge_entry(VertexIndex a, VertexIndex b, std::uint32_t time) const {
    const bool a_locked = flags_[a] & kLocked, b_locked = flags_[b] & kLocked;
    if (a_locked && b_locked) return std::nullopt;
    if (b_locked) std::swap(a, b);
    const Placement at = placement(a, b, plain_quadric(a) + plain_quadric(b));
    return HeapEntry{queue_key(a, b, at), a, b, time};
  }

  // One or two faces on edge (a, b), and two run it in opposite directions.
  bool is_manifold_oriented_edge(VertexIndex a, VertexIndex b) const {
    int faces = 0, outgoing = 0;
    for (std::uint32_t f : vertex_faces_[a]) {
      const Face& face = faces_[f];
      if (!has_vertex(face, b)) continue;
      ++faces;
      const int k = face[0] == a ? 0 : (face[1] == a ? 1 : 2);
      outgoing += face[(k + 1) % 3] == b;
    }
    return faces == 1 || (faces == 2 && outgoing == 1);
  }

  // (These three test both ends with bitwise operators: one branch on the answer, none on
  // which end decided it.)
  bool is_dead(const HeapEntry& e) const { return !(flags_[e.v0] & flags_[e.v1] & kAlive); }
  // A collapse at an end queued the edge again after this entry.
  bool is_superseded(const HeapEntry& e) const { return (int(requeued_[e.v0] > e.time) | int(requeued_[e.v1] > e.time)) != 0; }
  // An end changed after the entry was costed.
  bool is_dated(const HeapEntry& e) const { return (int(modified_[e.v0] > e.time) | int(modified_[e.v1] > e.time)) != 0; }
  // An entry that stands for nothing: in a lazy queue a dated entry is usually its edge's only
  // one (take_current costs it again; a flagged edge may have a duplicate, popped in turn), so
  // only entries of a removed vertex and entries a collapse at an end superseded go.
  bool is_obsolete(const HeapEntry& e) const { return is_dead(e) || (lazy_ ? is_superseded(e) : is_dated(e)); }

  // Lazy re-costing: a collapse costs only the edges it creates (collapse()); an edge it
  // changed keeps its entry, whose key is (nearly) a lower bound of its new cost: a merged
  // quadric is the old one plus a positive semi-definite one, so its minimum is no lower.
  // (Nearly: place() prefers endpoints and damps singular directions, and VG's key is Q_v at
  // Q's point.) When a dated entry reaches the front it is costed here: if its cost rose it
  // goes back into the queue (false); otherwise it is taken now with its new key, the cheapest
  // left. An edge whose ends change k times before it is popped is costed once, not k times.
  // Under an eager queue (a caller's CollapseCost, whose costs need not grow) every edge at a
  // changed vertex was queued again, so a dated entry is dropped.
  bool take_current(Lane& lane, HeapEntry& entry) {
    if (is_dead(entry)) return false;
    if (!is_dated(entry)) return true;
    if (!lazy_ || is_superseded(entry)) return false;
    // The end changed last first, as the collapse that changed it would have queued the edge:
    // between equal endpoint errors the first end stays, and on a CAD part's flat faces which
    // end moves decides whether the collapse is legal.
    const bool v1_newer = modified_[entry.v1] > modified_[entry.v0];
    const std::optional<HeapEntry> fresh =
        v1_newer ? edge_entry(entry.v1, entry.v0, lane.clock) : edge_entry(entry.v0, entry.v1, lane.clock);
    ++lane.requeued_edges;
    if (!fresh) return false;
    if (fresh->key > entry.key) {
      lane.heap.push(*fresh);
      return false;
    }
    entry = *fresh;
    return true;
  }

  // A refused collapse leaves the queue until a change next to it: both ends are flagged, and
  // collapse() queues the edges between flagged vertices again. So does a collapse past
  // max_error in a lazy queue (an eager one queues every edge at a changed vertex anyway).
  void set_aside(const CollapseProfile& p) {
    flags_[p.v0] |= kRejected;
    flags_[p.v1] |= kRejected;
  }

  // A collapse that cost nothing: its point is an endpoint whose error is 0 up to rounding
  // (place()'s first test), as on a CAD part's flat faces. After such a collapse a lazy queue
  // still queues every edge at the merged vertex: among the many free collapses of a flat
  // region the queue's order (last queued first) then goes on around the vertex just merged.
  // Left in their old places, fandisk's flat regions were merged into hubs of many faces whose
  // collapses were refused again and again (3x the refusals, 1.9x the instructions).
  // (Asked before the collapse: the merged quadric is summed here as collapse() will sum it.)
  bool was_free(const CollapseProfile& p) const {
    const Quadric q = plain_quadric(p.v0) + plain_quadric(p.v1);
    return p.placement.error <= 1e-12 * (q.a00 + q.a11 + q.a22 + std::abs(q.c)) + 1e-300;
  }

  // Fills the profile for a current heap entry (callers call take_current first); false when the
  // edge has no face left.
  bool prepare(const HeapEntry& e, CollapseProfile& p) {
    p.v0 = e.v0;
    p.v1 = e.v1;
    p.num_removed = 0;
    p.removed[1] = kNoFace;
    for (std::uint32_t f : vertex_faces_[e.v0]) {
      if (!has_vertex(faces_[f], e.v1)) continue;
      if (p.num_removed == 2) return false;  // cannot happen on unlocked vertices
      p.removed[p.num_removed] = f;
      p.opposite[p.num_removed] = third_vertex(faces_[f], e.v0, e.v1);
      ++p.num_removed;
    }
    if (p.num_removed == 0) return false;
    place_and_measure(e.v0, e.v1, p);
    return true;
  }

  // (prepare() leaves kNoFace in removed[1] on a boundary edge: no branch on num_removed.)
  bool is_removed(const CollapseProfile& p, std::uint32_t f) const {
    return (int(f == p.removed[0]) | int(f == p.removed[1])) != 0;
  }

  // Legality filters: link condition, topology table, normal change.
  bool legal(Lane& lane, const CollapseProfile& p) {
    // Link condition (Dey et al. 1999): the common neighbours of v0 and v1 must be exactly
    // the opposite vertices, or the collapse pinches the surface.
    std::size_t common = 0;
    if (lane.mark_id > UINT32_MAX - 2) fresh_mark(lane);  // keep both marks below from wrapping
    const std::uint32_t v0_neighbor = fresh_mark(lane);
    mark_neighbors(v0_neighbor, p.v0);
    const std::uint32_t counted = fresh_mark(lane);
    for (std::uint32_t f : vertex_faces_[p.v1])
      for (VertexIndex w : faces_[f]) {
        // Without branches (whether a corner is a common neighbour is not predictable): a
        // corner that is not one gets its own mark back.
        const bool common_neighbor = (int(w != p.v0) & int(w != p.v1) & int(mark_[w] == v0_neighbor)) != 0;
        mark_[w] = select_if(common_neighbor, counted, mark_[w]);
        common += common_neighbor;
      }
    if (common != static_cast<std::size_t>(p.num_removed)) return false;

    // Topology table:
    //   interior edge (2 faces) joining two boundary vertices  -> reject (pinches a bridge)
    //   opposite vertex interior with 3 faces                  -> reject (folds a tetrahedron)
    //   opposite vertex whose only face is removed             -> reject (leaves it isolated)
    //   v0 locked, removed face on a non-manifold or misoriented
    //   edge (v0, opposite)                                    -> reject (breaks up a non-manifold fan)
    const bool b0 = flags_[p.v0] & kBoundary, b1 = flags_[p.v1] & kBoundary;
    if (p.num_removed == 2 && b0 && b1) return false;
    for (int i = 0; i < p.num_removed; ++i) {
      const VertexIndex c = p.opposite[i];
      const std::size_t degree = vertex_faces_[c].size();
      if (degree <= 1 || (!(flags_[c] & kBoundary) && degree <= 3)) return false;
      // A free v0 has only manifold, consistent edges; a locked one may not, and taking one
      // face off a 3-face edge leaves two that may run the same way (found by fuzz_simplify).
      if ((flags_[p.v0] & kLocked) && !is_manifold_oriented_edge(p.v0, c)) return false;
    }

    // Normal change: no remaining face may turn by more than the limit or become degenerate.
    const Vec3 x = p.placement.position;
    std::vector<MovedFace>& moved_faces = lane.moved_faces;
    moved_faces.clear();
    for (VertexIndex moved : {p.v0, p.v1}) {
      for (std::uint32_t f : vertex_faces_[moved]) {
        if (is_removed(p, f)) continue;
        const Face& face = faces_[f];
        Vec3 corners[3] = {positions_[face[0]], positions_[face[1]], positions_[face[2]]};
        const Vec3 n_old = cross(corners[1] - corners[0], corners[2] - corners[0]);
        // (Branches, though mispredicted: an index computed from the comparisons took the
        // corners out of registers, fandisk's loop +20%.)
        for (int k = 0; k < 3; ++k)
          if (face[k] == p.v0 || face[k] == p.v1) corners[k] = x;
        const Vec3 n_new = cross(corners[1] - corners[0], corners[2] - corners[0]);
        const double len_new = norm(n_new);
        if (is_degenerate_triangle(corners[0], corners[1], corners[2], len_new)) return false;  // a zero-area face
        const double len_old = norm(n_old);
        if (len_old > 0 && dot(n_old, n_new) < cos_max_normal_change_ * len_old * len_new) return false;
        if (prevent_folds_) moved_faces.push_back({f, n_old, n_new});
      }
    }
    return !(prevent_folds_ && folds_an_edge(moved_faces, p));
  }

  // With prevent_folds: true when a face around the merged vertex would fold back onto a face
  // across one of its edges (normals more than ~154° apart) where the two did not fold before.
  // The normal-change limit bounds each face's turn, not the angle between neighbours: a thin
  // plate whose rim is collapsed away ends as two sheets back to back.
  bool folds_an_edge(const std::vector<MovedFace>& moved_faces, const CollapseProfile& p) {
    constexpr double kFoldCosine = -0.9;
    auto folded = [&](const Vec3& a, const Vec3& b) { return dot(a, b) < kFoldCosine * norm(a) * norm(b); };
    auto renamed = [&](VertexIndex v) { return v == p.v1 ? p.v0 : v; };
    for (const MovedFace& m : moved_faces) {
      const Face& face = faces_[m.face];
      for (int k = 0; k < 3; ++k) {
        VertexIndex a = renamed(face[k]), b = renamed(face[(k + 1) % 3]);
        if (a == p.v0) std::swap(a, b);  // a: the end that does not move
        for (std::uint32_t g : vertex_faces_[a]) {
          if (g == m.face || is_removed(p, g)) continue;
          const Face& other = faces_[g];
          const bool shares = b == p.v0 ? has_vertex(other, p.v0) || has_vertex(other, p.v1) : has_vertex(other, b);
          if (!shares) continue;
          Vec3 g_old = cross(positions_[other[1]] - positions_[other[0]], positions_[other[2]] - positions_[other[0]]);
          Vec3 g_new = g_old;
          for (const MovedFace& n : moved_faces)
            if (n.face == g) g_new = n.n_new;
          if (folded(m.n_new, g_new) && !folded(m.n_old, g_old)) return true;
        }
      }
    }
    return false;
  }

  void collapse(Lane& lane, const CollapseProfile& p, SimplifyResult& result) {
    const VertexIndex v0 = p.v0, v1 = p.v1;
    // v0's neighbours before the collapse: their edges with v0 keep their entries, unless every
    // edge at v0 is queued again (an eager queue, a free collapse).
    const bool requeue_all = !lazy_ || was_free(p);
    std::uint32_t before = 0;  // read only when !requeue_all
    if (!requeue_all) {
      before = fresh_mark(lane);
      mark_neighbors(before, v0);
    }
    for (int i = 0; i < p.num_removed; ++i) {
      const std::uint32_t f = p.removed[i];
      face_alive_[f] = 0;
      vertex_faces_.remove(p.opposite[i], f);
      vertex_faces_.remove(v0, f);
    }
    for (std::uint32_t f : vertex_faces_[v1]) {
      if (!face_alive_[f]) continue;
      for (VertexIndex& w : faces_[f]) w = w == v1 ? v0 : w;  // a select, not a branch
    }
    vertex_faces_.merge_into(v0, v1, [&](std::uint32_t f) { return face_alive_[f] != 0; });
    if (lane.partition)
      lane.faces_removed += static_cast<std::size_t>(p.num_removed);
    else
      faces_alive_ -= static_cast<std::size_t>(p.num_removed);

    positions_[v0] = p.placement.position;
    if (p.placement.kind == PlacementKind::endpoint1)
      origin_[v0] = origin_[v1];
    else if (p.placement.kind != PlacementKind::endpoint0)
      origin_[v0] = kNoOrigin;
    plain_quadric(v0) += plain_quadric(v1);
    if (weighted_) cost_quadric(v0) += cost_quadric(v1);
    if (!vertex_weights_.empty()) vertex_weights_[v0] = std::max(vertex_weights_[v0], vertex_weights_[v1]);
    flags_[v0] = static_cast<std::uint8_t>(flags_[v0] | (flags_[v1] & kBoundary));
    flags_[v1] = 0;
    ++lane.clock;
    modified_[v0] = modified_[v1] = lane.clock;
    ++result.collapses;
    result.max_error = std::max(result.max_error, p.error);

    // Costs for the edges at v0: in a lazy queue only for the edges the collapse made (from
    // v1's side) and for those that may have left the queue refused (both ends flagged; at
    // worst a duplicate); eagerly for all. Neighbours refused earlier get another chance since
    // their surroundings changed.
    // The ring is gathered first without branches (whether a corner was seen is not
    // predictable), every corner written and the count advanced only for a new one, then
    // queued in the order the branchy loop pushed.
    if (requeue_all) requeued_[v0] = lane.clock;
    const std::uint32_t after = fresh_mark(lane);  // a wrap clears `before`: every edge is then pushed
    mark_[v0] = after;
    const std::size_t corners = 3 * vertex_faces_[v0].size();
    if (lane.ring.size() < corners) {
      lane.ring.resize(corners);
      lane.ring_had_edge.resize(corners);
    }
    VertexIndex* const ring = lane.ring.data();
    std::uint8_t* const had_edge = lane.ring_had_edge.data();
    std::size_t ring_size = 0;
    for (std::uint32_t f : vertex_faces_[v0])
      for (VertexIndex w : faces_[f]) {
        const std::uint32_t seen = mark_[w];
        ring[ring_size] = w;
        had_edge[ring_size] = seen == before;
        ring_size += seen != after;
        mark_[w] = after;
      }
    for (std::size_t i = 0; i < ring_size; ++i)
      if (requeue_all || !had_edge[i] || (flags_[v0] & flags_[ring[i]] & kRejected)) push_edge(lane, v0, ring[i]);
    for (std::size_t i = 0; i < ring_size; ++i) {
      const VertexIndex w = ring[i];
      if (!(flags_[w] & kRejected)) continue;
      flags_[w] &= static_cast<std::uint8_t>(~kRejected);
      lane.second_ring.clear();
      for_each_neighbor(lane, w, [&](VertexIndex u) { lane.second_ring.push_back(u); });
      for (VertexIndex u : lane.second_ring)
        if (u != v0 && (flags_[u] & kRejected)) push_edge(lane, w, u);
    }
  }

  // One partition's share of a round.
  void run_partition(Lane& lane, std::uint32_t threshold, double max_error) {
    HeapEntry entry;
    while (!lane.done && lane.heap.pop_at_most(threshold, entry)) {
      if (is_obsolete(entry)) continue;
      if (!is_deep(entry.v0, entry.v1)) {
        lane.leftover.push_back(entry);
        continue;
      }
      CollapseProfile profile;
      if (!take_current(lane, entry) || !prepare(entry, profile)) continue;
      if (profile.error > max_error) {
        lane.error_limited = true;
        if (lazy_) set_aside(profile);
        continue;
      }
      if (!legal(lane, profile)) {
        ++lane.tally.rejected_collapses;
        set_aside(profile);
        continue;
      }
      const std::size_t merged = vertex_faces_[profile.v0].size() + vertex_faces_[profile.v1].size();
      if (lane.faces_removed + static_cast<std::size_t>(profile.num_removed) > lane.face_budget) {
        lane.leftover.push_back(entry);
        lane.done = true;
        return;
      }
      if (!vertex_faces_.make_room(profile.v0, merged)) {  // its region is full: leave it to the serial phase
        lane.leftover.push_back(entry);
        continue;
      }
      collapse(lane, profile, lane.tally);
      maybe_compact_heap(lane);
    }
  }

  // True when neither end nor any neighbour of either end has a neighbour in another
  // partition. Then everything a collapse of the edge reads or writes (the two rings, the
  // faces around them, the second ring it re-costs) belongs to the partition, and no
  // collapse elsewhere writes any of it: a collapse elsewhere changes only vertices that are
  // not cut and faces around them, and merging two such vertices adds no edge between
  // partitions, so the cut vertices stay the same through the phase.
  bool is_deep(VertexIndex v0, VertexIndex v1) const {
    if ((flags_[v0] | flags_[v1]) & kCut) return false;
    for (VertexIndex v : {v0, v1})
      for (std::uint32_t f : vertex_faces_[v])
        for (VertexIndex w : faces_[f])
          if (flags_[w] & kCut) return false;
    return true;
  }

  // The end of the parallel phase: one queue from every partition's, in partition order
  // (obsolete entries dropped), clocks and marks above every lane's, the tallies summed.
  void join_partitions(SimplifyResult& result) {
    std::size_t entries = 0;
    for (const Lane& lane : lanes_) entries += lane.heap.size() + lane.leftover.size();
    Entries all;
    all.reserve(entries);
    auto stale = [this](const HeapEntry& e) { return is_obsolete(e); };
    for (Lane& lane : lanes_) {
      const std::size_t from = all.size();
      lane.heap.take_all(all);
      all.insert(all.end(), lane.leftover.begin(), lane.leftover.end());
      GrowingEntries().swap(lane.leftover);
      all.erase(std::remove_if(all.begin() + static_cast<std::ptrdiff_t>(from), all.end(), stale), all.end());
      serial_.clock = std::max(serial_.clock, lane.clock);
      serial_.mark_id = std::max(serial_.mark_id, lane.mark_id);
      serial_.error_limited = serial_.error_limited || lane.error_limited;
      result.collapses += lane.tally.collapses;
      result.parallel_collapses += lane.tally.collapses;
      result.rejected_collapses += lane.tally.rejected_collapses;
      result.requeued_edges += lane.requeued_edges;
      result.max_error = std::max(result.max_error, lane.tally.max_error);
    }
    lanes_.clear();
    serial_.heap.assign(std::move(all));
    for (std::uint8_t& f : flags_) f &= static_cast<std::uint8_t>(~kCut);
    vertex_faces_.join_regions();
    give_back_freed_memory();
  }

  void report_progress() {
    if (observer_ == nullptr || faces_alive_ > next_report_) return;
    observer_->on_progress(planned_ ? std::min(1.0, double(input_faces_ - faces_alive_) / double(planned_))
                                    : 1.0);
    next_report_ = faces_alive_ > report_every_ ? faces_alive_ - report_every_ : 0;
  }

  // Drops obsolete entries once the heap holds 3× the live edges, bounding its memory (at 4×
  // the heap was the engine's largest allocation). A lazy queue keeps dated entries, and a
  // duplicate queued for a flagged edge stays until popped, so a compaction may leave the heap
  // above the line: the next then waits until the heap has doubled (no scan of the whole heap
  // at every collapse). When and how often the heap is compacted changes no pop order.
  void maybe_compact_heap(Lane& lane) {
    const std::size_t faces = lane.partition ? lane.faces_at_start - lane.faces_removed : faces_alive_;
    const std::size_t live_edges = faces * 3 / 2 + 1024;
    if (lane.heap.size() < std::max(3 * live_edges, lane.compact_at)) return;
    lane.heap.remove_if([this](const HeapEntry& e) { return is_obsolete(e); });
    lane.compact_at = 2 * lane.heap.size();
  }

  const Mesh& input_;
  std::vector<std::array<float, 3>> input_positions_float_;  // see keep_input_positions_as_floats
  Vec3 input_position(VertexIndex u) const {
    if (input_positions_float_.empty()) return input_.positions[u];
    const std::array<float, 3>& p = input_positions_float_[u];
    return {p[0], p[1], p[2]};
  }
  UnitFrame frame_;
  double cos_max_normal_change_;
  bool prevent_folds_ = false;
  std::size_t input_faces_ = 0;  // the input may give its faces up after set-up (simplify(Mesh&&))
  int phase_depth_ = 0;          // the parallel phase's rung (0: none)
  bool has_boundary_ = false;    // some input edge has one face (a vertex carries kBoundary)
  bool area_weights_ = false;  // a face's plane weighs its area, not 1
  double area_floor_factor_ = 0;  // area weights: + this x the median face area (SimplifyOptions::area_floor)
  double boundary_weight_ = 0;
  // The per-vertex and per-face arrays are huge-page backed when large (core/large_array.h).
  detail::LargeArray<Vec3> positions_;  // unit frame
  detail::LargeArray<Face> faces_;
  detail::LargeArray<std::uint8_t> face_alive_;
  std::size_t faces_alive_ = 0;
  std::size_t dropped_repeated_index_faces_ = 0;
  detail::VertexFaceLists vertex_faces_;
  // Engine index -> input index (see reorder_spatially).
  std::vector<VertexIndex> input_vertex_;
  detail::LargeArray<std::uint32_t> input_face_;
  // Per vertex, under VG, the cost quadric Q_v = Σ V(t)^P K_t (orders the queue) and right
  // after it the plain quadric Q (places the vertex, gives the error). Interleaved, both come
  // in with one memory access: a separate array doubled the cache misses (VG +15–40% over QB).
  // The pair is 192 bytes, three cache lines (whole lines in an array of 256 KiB or more,
  // which starts on a huge-page boundary); the cost quadric first, on a 16-byte boundary, for
  // evaluate_aligned_sum.
  struct alignas(16) VertexQuadrics {
    CostQuadric cost;
    Quadric plain;
  };
  static_assert(sizeof(VertexQuadrics) == 192, "a vertex's quadrics fill three cache lines");
  static_assert(offsetof(VertexQuadrics, cost) == 0 && offsetof(CostQuadric, pairs) == 0,
                "the cost pairs start on the record's 16-byte boundary");
  bool weighted_ = false;
  const CollapseCost* custom_cost_ = nullptr;  // orders the queue instead of the quadrics when set
  bool lazy_ = true;  // re-cost dated entries when popped (take_current); not under a CollapseCost
  std::vector<float> vertex_weights_;          // with custom_cost_: per vertex, merged by max
  detail::LargeArray<Quadric> quadrics_;                  // QB
  detail::LargeArray<VertexQuadrics> weighted_quadrics_;  // VG
  Quadric& plain_quadric(VertexIndex v) { return weighted_ ? weighted_quadrics_[v].plain : quadrics_[v]; }
  const Quadric& plain_quadric(VertexIndex v) const { return weighted_ ? weighted_quadrics_[v].plain : quadrics_[v]; }
  CostQuadric& cost_quadric(VertexIndex v) { return weighted_quadrics_[v].cost; }
  const CostQuadric& cost_quadric(VertexIndex v) const { return weighted_quadrics_[v].cost; }
  std::vector<double> face_weight_;  // VG with crease visibility or P != 2: V(t)^P per face (see face_weight)
  const std::vector<float>* input_visibility_ = nullptr;  // VG: SimplifyOptions::face_visibility, during set-up
  detail::LargeArray<std::uint8_t> flags_;
  detail::LargeArray<std::uint32_t> modified_;  // clock of the vertex's last change
  detail::LargeArray<std::uint32_t> requeued_;  // clock of the vertex's last collapse that queued all its edges
  static constexpr VertexIndex kNoOrigin = 0xffffffffu;
  detail::LargeArray<VertexIndex> origin_;  // input vertex whose exact position v holds, or kNoOrigin
  detail::LargeArray<std::uint32_t> mark_;  // see fresh_mark
  Lane serial_;                      // the serial loop's queue and scratch
  std::vector<Lane> lanes_;          // one per partition, during the parallel phase
  std::uint32_t first_threshold_ = 0;
  SimplifyObserver* observer_ = nullptr;
  std::size_t planned_ = 0, report_every_ = 1, next_report_ = 0;
};

}  // namespace

void check_options(const SimplifyOptions& options) {
  const SimplifyOptions& o = options;
  if (!(o.target_ratio >= 0 && o.target_ratio <= 1))
    throw OptionError(&o.target_ratio, "SimplifyOptions::target_ratio",
                      "must be in (0, 1] (0: unset), got " + std::to_string(o.target_ratio));
  if (!(o.max_error >= 0)) throw OptionError(&o.max_error, "SimplifyOptions::max_error", "must be >= 0");
  if (!(o.area_floor >= 0) || !std::isfinite(o.area_floor))
    throw OptionError(&o.area_floor, "SimplifyOptions::area_floor", "must be a finite number >= 0");
  if (o.area_floor > 0 && o.quadric_weights != QuadricWeights::area)
    throw OptionError(&o.area_floor, "SimplifyOptions::area_floor", "applies to area weights only, not uniform");
  if (!(o.boundary_weight >= 0) || !std::isfinite(o.boundary_weight))
    throw OptionError(&o.boundary_weight, "SimplifyOptions::boundary_weight", "must be a finite number >= 0");
  if (!(o.max_normal_change_deg > 0 && o.max_normal_change_deg <= 180))
    throw OptionError(&o.max_normal_change_deg, "SimplifyOptions::max_normal_change_deg",
                      "must be in (0, 180] degrees");
  if (!(o.visibility_exponent > 0) || !std::isfinite(o.visibility_exponent))
    throw OptionError(&o.visibility_exponent, "SimplifyOptions::visibility_exponent", "must be a finite number > 0");
  const bool has_target = o.target_faces > 0 || o.target_ratio > 0;
  if (!has_target && std::isinf(o.max_error))
    throw OptionError(nullptr, "SimplifyOptions",
                      "needs a target (target_faces or target_ratio) or a finite max_error");
}

namespace {

void check_visibility(const Mesh& input, const SimplifyOptions& options) {
  if (!options.vertex_weights.empty() && options.vertex_weights.size() != input.num_vertices()) {
    throw OptionError(&options.vertex_weights, "SimplifyOptions::vertex_weights",
                      "must hold one weight per vertex (" + std::to_string(input.num_vertices()) + "), got " +
                          std::to_string(options.vertex_weights.size()));
  }
  if (options.method != SimplifyMethod::vg) return;
  if (options.face_visibility.size() != input.num_faces()) {
    throw UsageError("VG simplification needs V of every face: got " + std::to_string(options.face_visibility.size()) +
                     " values for " + std::to_string(input.num_faces()) + " faces");
  }
  // One branch-free pass (it vectorises) and the search for the culprit only when it fails.
  bool all_in_range = true;
  for (const float v : options.face_visibility) all_in_range &= v >= 0.0f && v <= 1.0f;
  if (all_in_range) return;
  for (std::size_t f = 0; f < input.num_faces(); ++f) {
    const float v = options.face_visibility[f];
    if (!(v >= 0.0f && v <= 1.0f)) {
      throw UsageError("visibility of face " + std::to_string(f) + " is " + std::to_string(v) + ", not in [0, 1]");
    }
  }
}

std::size_t resolve_target(const Mesh& input, const SimplifyOptions& options) {
  return options.target_faces > 0
             ? options.target_faces
             : static_cast<std::size_t>(std::llround(options.target_ratio * double(input.num_faces())));
}

// How deep a run to `target` takes the parallel phase (0: no phase): not for a caller's cost
// (which need not be thread-safe), not for a mesh of one partition, and only to a rung the
// target is under (the phase ends at or above alive - Σ budgets >= alive - budget·alive
// faces, so it cannot pass the target). The thread count plays no part: one thread runs the
// same phase.
int parallel_phase_depth(const Mesh& input, const SimplifyOptions& options, std::size_t target) {
  if (options.serial_collapses || options.collapse_cost != nullptr || input.num_vertices() < 2 * kPartitionVertices)
    return 0;
  std::size_t alive = 0;  // the faces the engine starts with (repeated indices dropped)
  for (const Face& f : input.faces) alive += f[0] != f[1] && f[1] != f[2] && f[0] != f[2];
  int depth = 0;
  for (int d = 1; d <= kDeepestPhase; ++d)
    if (target <= alive - alive * kPhaseRungs[d - 1].budget_per_mille / 1000) depth = d;
  return depth;
}

// Seconds since the last lap (or since it was made).
class StageClock {
 public:
  double lap() {
    const auto now = std::chrono::steady_clock::now();
    const double seconds = std::chrono::duration<double>(now - last_).count();
    last_ = now;
    return seconds;
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

SimplifyResult start_result(const Mesh& input) {
  SimplifyResult result;
  result.faces_in = input.num_faces();
  result.vertices_in = input.num_vertices();
  return result;
}

void finish_result(Simplified& out, std::chrono::steady_clock::time_point start) {
  if (out.result.collapses == 0 && out.result.faces_in <= out.result.target_faces)
    out.result.stop_reason = StopReason::nothing_to_do;
  out.result.faces_out = out.mesh.num_faces();
  out.result.vertices_out = out.mesh.num_vertices();
  out.result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

namespace {

// simplify() for both overloads. `owned`: the caller's mesh, given up (the same object as
// `input`): its faces are dropped once the engine has its own copy.
Simplified simplify_one(const Mesh& input, Mesh* owned, const SimplifyOptions& options, SimplifyObserver* observer) {
  const auto start = std::chrono::steady_clock::now();
  check_options(options);
  require_valid(input, "simplify input");
  check_visibility(input, options);

  Simplified out;
  out.result = start_result(input);
  out.result.target_faces = resolve_target(input, options);
  if (out.result.faces_in <= out.result.target_faces) {
    out.mesh = owned != nullptr ? std::move(*owned) : input;
  } else {
    SimplifyStageSeconds& stage = out.result.stage_seconds;
    StageClock clock;
    const int phase_depth = parallel_phase_depth(input, options, out.result.target_faces);
    CollapseEngine engine(input, options, phase_depth, options.threads, owned);
    out.result.locked_vertices = engine.locked_vertices();
    out.result.dropped_faces = engine.dropped_repeated_index_faces();
    engine.set_observer(observer, out.result.target_faces);
    stage.setup = clock.lap();
    if (phase_depth > 0) {
      engine.run_parallel_phase(options.max_error, options.threads, out.result);
      stage.parallel_phase = clock.lap();
    }
    std::vector<HeapEntry> deferred;
    engine.run(out.result.target_faces, options.max_error, out.result, deferred, false);
    if (observer) observer->on_progress(1.0);
    stage.serial = clock.lap();
    out.mesh = engine.extract();
    stage.extract = clock.lap();
  }
  finish_result(out, start);
  return out;
}

}  // namespace

Simplified simplify(const Mesh& input, const SimplifyOptions& options, SimplifyObserver* observer) {
  return simplify_one(input, nullptr, options, observer);
}

Simplified simplify(Mesh&& input, const SimplifyOptions& options, SimplifyObserver* observer) {
  return simplify_one(input, &input, options, observer);
}

std::vector<Simplified> simplify_levels(const Mesh& input, const SimplifyOptions& options,
                                        const std::vector<std::size_t>& targets, SimplifyObserver* observer) {
  const auto start = std::chrono::steady_clock::now();
  if (targets.empty()) throw UsageError("no target face counts given");
  for (std::size_t t : targets)
    if (t == 0) throw UsageError("target face counts must be > 0");
  SimplifyOptions checked = options;
  checked.target_faces = *std::min_element(targets.begin(), targets.end());
  check_options(checked);
  require_valid(input, "simplify input");
  check_visibility(input, options);

  // Largest target first; equal targets share one snapshot. One engine, one collapse sequence
  // without the parallel phase, snapshotted at every target: each level is what simplify()
  // with serial_collapses gives. (An engine per rung of the phase, each starting over from
  // the input, made compare's seven levels on the dragon 1.7x the wall time and 2.5x the CPU
  // of one sequence, with more image error at most levels: docs/simplify.md.)
  std::vector<std::size_t> levels(targets.size());
  for (std::size_t i = 0; i < levels.size(); ++i) levels[i] = i;
  std::stable_sort(levels.begin(), levels.end(), [&](std::size_t x, std::size_t y) { return targets[x] > targets[y]; });

  std::vector<Simplified> out(targets.size());
  {
    StageClock clock;
    CollapseEngine engine(input, options, 0, options.threads);
    engine.set_observer(observer, targets[levels.back()]);
    SimplifyResult running = start_result(input);
    running.locked_vertices = engine.locked_vertices();
    running.dropped_faces = engine.dropped_repeated_index_faces();
    running.stage_seconds.setup = clock.lap();
    std::vector<HeapEntry> deferred;
    std::optional<HeapEntry> pending;  // where the previous level stopped, taken first by the next
    for (std::size_t k = 0; k < levels.size(); ++k) {
      const std::size_t target = targets[levels[k]];
      Simplified& level = out[levels[k]];
      if (k > 0 && target == targets[levels[k - 1]]) {
        level = out[levels[k - 1]];
        continue;
      }
      running.target_faces = target;
      if (input.num_faces() <= target) {
        level.mesh = input;
        level.result = running;
        finish_result(level, start);
        continue;
      }
      deferred.clear();
      const HeapEntry* first = pending ? &*pending : nullptr;
      engine.run(target, options.max_error, running, deferred, true, first);
      running.stage_seconds.serial += clock.lap();
      pending.reset();
      if (deferred.empty()) {  // reached (or stuck): exactly where simplify() to this target ends
        SimplifyResult result = running;
        std::vector<HeapEntry> none;
        engine.run(target, options.max_error, result, none, false);  // only sets the stop reason
        result.stage_seconds.serial += clock.lap();
        level.mesh = engine.extract();
        level.result = result;
      } else if (!engine.has_boundary()) {
        // A closed mesh: run() takes the deferred collapse and nothing else, popping nothing,
        // and the next level would take that same entry first: take it here, no copy needed.
        engine.run(target, options.max_error, running, deferred, false);
        running.stage_seconds.serial += clock.lap();
        level.mesh = engine.extract();
        level.result = running;
      } else {
        // simplify() to this target would now keep looking for a collapse that hits it exactly
        // and consume the queue doing so: do that on a copy, and go on from here with the entry.
        CollapseEngine finisher = engine;
        finisher.set_observer(nullptr, target);
        level.result = running;
        finisher.run(target, options.max_error, level.result, deferred, false);
        level.result.stage_seconds.serial += clock.lap();
        level.mesh = finisher.extract();
        pending = deferred.front();
      }
      level.result.stage_seconds.extract = clock.lap();
      finish_result(level, start);
    }
  }
  if (observer) observer->on_progress(1.0);
  return out;
}

}  // namespace visimp
