// Private to simplify: the faces around each vertex, all lists in one pool.
//
// A std::vector per vertex cost 24 bytes of header plus a heap block (and its malloc
// header) per vertex, and put each list wherever malloc had room: at 14M faces the lists
// were a fifth of the engine's memory and every visit of a neighbour's list was a cache
// miss. Here a list is a slice of one array, laid out in vertex order, so lists of vertices
// close in the (spatially sorted) vertex order are close in memory. A list that outgrows its
// slice moves to the end of the pool; once the slices left behind outweigh the live ones,
// the pool is rewritten in vertex order.
#pragma once

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "../core/large_array.h"

namespace visimp::detail {

class VertexFaceLists {
 public:
  struct Range {
    const std::uint32_t* first;
    const std::uint32_t* last;
    const std::uint32_t* begin() const { return first; }
    const std::uint32_t* end() const { return last; }
    std::size_t size() const { return static_cast<std::size_t>(last - first); }
    bool empty() const { return first == last; }
    std::uint32_t operator[](std::size_t i) const { return first[i]; }
  };

  /// Lists for `vertex_count` vertices from faces given as triples; faces for which
  /// `skip(f)` is true are left out.
  template <class Faces, class Skip>
  void build(std::size_t vertex_count, const Faces& faces, Skip skip) {
    slots_.assign(vertex_count, Slot{});
    for (std::size_t f = 0; f < faces.size(); ++f)
      if (!skip(f))
        for (auto v : faces[f]) ++slots_[v].capacity;
    std::size_t offset = 0;
    for (Slot& s : slots_) {
      s.offset = checked_offset(offset);
      offset += s.capacity;
    }
    // Room for lists that grow before the first rewrite, and for split_into_regions's gaps
    // (a quarter, plus 8 a region of at least 64 vertices) without moving the pool.
    pool_.reserve(offset + offset / 4 + vertex_count / 8 + 64);
    pool_.assign(offset, 0);
    for (std::size_t f = 0; f < faces.size(); ++f)
      if (!skip(f))
        for (auto v : faces[f]) {
          Slot& s = slots_[v];
          pool_[s.offset + s.size++] = static_cast<std::uint32_t>(f);
        }
    dead_ = 0;
  }

  Range operator[](std::size_t v) const {
    const Slot& s = slots_[v];
    return {pool_.data() + s.offset, pool_.data() + s.offset + s.size};
  }

  /// Removes face f from v's list (the last entry takes its place).
  void remove(std::size_t v, std::uint32_t f) {
    Slot& s = slots_[v];
    std::uint32_t* list = pool_.data() + s.offset;
    // The whole (short) list is scanned with a select, backwards so that the first match wins:
    // where f sits is not predictable, and a branch on it was mispredicted about once a call.
    std::uint32_t at = s.size;
    for (std::uint32_t i = s.size; i-- > 0;) {
      const std::uint32_t mask = 0u - static_cast<std::uint32_t>(list[i] == f);  // a mask, not a branch
      at = (i & mask) | (at & ~mask);
    }
    if (at == s.size) return;
    list[at] = list[--s.size];
  }

  /// Appends the faces of `from` for which `keep(f)` is true to `to`'s list, and empties
  /// `from`'s (the collapse merging `from` into `to`).
  template <class Keep>
  void merge_into(std::size_t to, std::size_t from, Keep keep) {
    reserve(to, slots_[to].size + slots_[from].size);
    Slot& t = slots_[to];
    Slot& s = slots_[from];
    for (std::uint32_t i = 0; i < s.size; ++i) {
      const std::uint32_t f = pool_[s.offset + i];
      if (keep(f)) pool_[t.offset + t.size++] = f;
    }
    if (regions_.empty()) dead_ += s.capacity;  // regions are packed by their own rewrite
    s = Slot{};
  }

  /// Splits the pool into regions of `vertices_per_region` consecutive vertices, each holding
  /// its vertices' lists followed by room to grow (`slack` times their length). A list that
  /// outgrows its slice then moves within its region, never to the shared end: regions share
  /// no memory and the pool is not resized, so threads may change lists of vertices in
  /// different regions at once (simplify's parallel phase).
  void split_into_regions(std::size_t vertices_per_region, double slack) {
    vertices_per_region_ = vertices_per_region;
    const std::size_t count = (slots_.size() + vertices_per_region - 1) / vertices_per_region;
    std::vector<std::size_t> live(count, 0);
    for (std::size_t v = 0; v < slots_.size(); ++v) live[v / vertices_per_region] += slots_[v].size;
    std::size_t total = 0;
    for (std::size_t n : live) total += n + static_cast<std::size_t>(slack * double(n)) + 8;
    for (const Region& region : regions_) region_compactions_ += region.compactions;
    if (spread_in_place(vertices_per_region, slack, live, total)) return;
    LargeArray<std::uint32_t> packed(total);
    regions_.assign(count, Region{});
    std::size_t at = 0;
    for (std::size_t r = 0; r < count; ++r) {
      regions_[r].begin = at;
      const std::size_t last = std::min(slots_.size(), (r + 1) * vertices_per_region);
      for (std::size_t v = r * vertices_per_region; v < last; ++v) {
        Slot& s = slots_[v];
        std::copy_n(pool_.begin() + s.offset, s.size, packed.begin() + at);
        s.offset = checked_offset(at);
        s.capacity = s.size;
        at += s.size;
      }
      regions_[r].next = at;
      at += static_cast<std::size_t>(slack * double(live[r])) + 8;
      regions_[r].end = at;
    }
    checked_offset(at);
    pool_.swap(packed);
    dead_ = 0;
  }

  /// split_into_regions without a second pool, when the lists are still as build() laid them
  /// out (packed in vertex order) and the gaps fit the pool's capacity: every list moves up (or stays),
  /// so moving them from the last down overwrites nothing unread. (A second pool was a
  /// transient of 170 MB at 14M faces, the parallel phase's peak.)
  bool spread_in_place(std::size_t vertices_per_region, double slack, const std::vector<std::size_t>& live,
                       std::size_t total) {
    if (!regions_.empty() || dead_ != 0 || total > pool_.capacity()) return false;
    checked_offset(total);
    std::size_t at = 0;
    for (const Slot& s : slots_) {
      if (s.offset != at || s.size != s.capacity) return false;
      at += s.size;
    }
    const std::size_t count = live.size();
    regions_.assign(count, Region{});
    at = 0;
    for (std::size_t r = 0; r < count; ++r) {
      regions_[r].begin = at;
      regions_[r].next = at + live[r];
      at += live[r] + static_cast<std::size_t>(slack * double(live[r])) + 8;
      regions_[r].end = at;
    }
    pool_.resize(total);  // within capacity: no reallocation
    for (std::size_t r = count; r-- > 0;) {
      std::size_t next = regions_[r].next;
      const std::size_t first = r * vertices_per_region, last = std::min(slots_.size(), first + vertices_per_region);
      for (std::size_t v = last; v-- > first;) {
        Slot& s = slots_[v];
        next -= s.size;
        if (next != s.offset)  // region 0's lists stay where they are
          std::copy_backward(pool_.begin() + s.offset, pool_.begin() + s.offset + s.size, pool_.begin() + next + s.size);
        s.offset = checked_offset(next);
      }
    }
    dead_ = 0;
    return true;
  }

  /// Back to one pool in vertex order (after the parallel phase).
  void join_regions() {
    for (const Region& region : regions_) region_compactions_ += region.compactions;
    regions_.clear();
    compact();
  }

  /// With regions: true when v's list can grow to `needed` entries inside its region,
  /// rewriting the region's lists packed if that is what makes room. Without regions: true.
  bool make_room(std::size_t v, std::size_t needed) {
    if (regions_.empty() || needed <= slots_[v].capacity) return true;
    const std::size_t r = v / vertices_per_region_;
    if (regions_[r].end - regions_[r].next >= grown_capacity(needed)) return true;
    compact_region(r);
    return regions_[r].end - regions_[r].next >= grown_capacity(needed);
  }

  /// How often a region was rewritten packed to make room (for tests and traces).
  std::size_t region_compactions() const {
    std::size_t count = region_compactions_;
    for (const Region& region : regions_) count += region.compactions;
    return count;
  }

  std::size_t memory_bytes() const {
    return slots_.capacity() * sizeof(Slot) + pool_.capacity() * sizeof(std::uint32_t);
  }

 private:
  struct Slot {
    std::uint32_t offset = 0, size = 0, capacity = 0;
  };

  static std::uint32_t checked_offset(std::size_t offset) {
    if (offset > 0xffffffffu) throw std::length_error("simplify: more than 2^32 vertex-face incidences");
    return static_cast<std::uint32_t>(offset);
  }

  // Room for `needed` entries in v's slice: the list moves to the end of the pool with room to
  // grow (collapses keep merging into the same survivors). Before the pool would reallocate,
  // it is rewritten if a fifth of it is dead slices.
  static std::size_t grown_capacity(std::size_t needed) { return std::max<std::size_t>(needed + needed / 2, 8); }

  void reserve(std::size_t v, std::size_t needed) {
    if (needed <= slots_[v].capacity) return;
    const std::size_t capacity = grown_capacity(needed);
    if (!regions_.empty()) {  // make_room has made sure the region has it
      Region& r = regions_[v / vertices_per_region_];
      if (r.end - r.next < capacity) throw std::logic_error("VertexFaceLists: no room left in a region");
      Slot& s = slots_[v];
      std::copy_n(pool_.begin() + s.offset, s.size, pool_.begin() + r.next);
      s.offset = static_cast<std::uint32_t>(r.next);
      s.capacity = static_cast<std::uint32_t>(capacity);
      r.next += capacity;
      return;
    }
    if (pool_.size() + capacity > pool_.capacity() && dead_ > pool_.size() / 5) compact();
    Slot& s = slots_[v];
    const std::uint32_t offset = checked_offset(pool_.size());
    checked_offset(pool_.size() + capacity);
    pool_.resize(pool_.size() + capacity);
    std::copy_n(pool_.begin() + s.offset, s.size, pool_.begin() + offset);
    dead_ += s.capacity;
    s.offset = offset;
    s.capacity = static_cast<std::uint32_t>(capacity);
  }

  // Rewrites the pool in vertex order, each slice as long as its list (the dead slices go).
  void compact() {
    LargeArray<std::uint32_t> packed;
    std::size_t live = 0;
    for (const Slot& s : slots_) live += s.size;
    packed.reserve(live + live / 4);
    for (Slot& s : slots_) {
      const std::uint32_t offset = checked_offset(packed.size());
      packed.insert(packed.end(), pool_.begin() + s.offset, pool_.begin() + s.offset + s.size);
      s.offset = offset;
      s.capacity = s.size;
    }
    pool_.swap(packed);
    dead_ = 0;
  }

  // Rewrites region r's lists packed from its start, in vertex order.
  void compact_region(std::size_t r) {
    Region& region = regions_[r];
    const std::size_t first = r * vertices_per_region_, last = std::min(slots_.size(), first + vertices_per_region_);
    std::vector<std::uint32_t> packed;
    packed.reserve(region.next - region.begin);
    for (std::size_t v = first; v < last; ++v) {
      Slot& s = slots_[v];
      const std::uint32_t offset = static_cast<std::uint32_t>(region.begin + packed.size());
      packed.insert(packed.end(), pool_.begin() + s.offset, pool_.begin() + s.offset + s.size);
      s.offset = offset;
      s.capacity = s.size;
    }
    std::copy(packed.begin(), packed.end(), pool_.begin() + region.begin);
    region.next = region.begin + packed.size();
    ++region.compactions;  // per region: regions are rewritten by different threads at once
  }

  struct Region {
    std::size_t begin = 0, next = 0, end = 0;  // [begin, next) in use, [next, end) free
    std::size_t compactions = 0;
  };

  LargeArray<Slot> slots_;
  std::vector<Region> regions_;  // empty outside the parallel phase
  std::size_t vertices_per_region_ = 0;
  LargeArray<std::uint32_t> pool_;  // huge-page backed: core/large_array.h
  std::size_t dead_ = 0;  // entries of the pool no list uses
  std::size_t region_compactions_ = 0;  // of the regions already joined
};

}  // namespace visimp::detail
