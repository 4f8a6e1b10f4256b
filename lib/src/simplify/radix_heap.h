// Private to simplify: a radix heap (Ahuja, Mehlhorn, Orlin & Tarjan 1990) over 32-bit keys.
//
// Collapse costs are non-negative floats, whose IEEE bit patterns order like unsigned
// integers, and the queue is (almost) monotone: merged quadrics only grow, so a new cost is
// rarely below the last one popped. A radix heap exploits that: push is O(1) and a pop moves
// each item down at most 32 buckets over its life, all with sequential memory access — on a
// million-edge mesh this is several times faster than a binary heap, whose sifts miss cache.
// A key below the last popped key is clamped to it ("process next"), which is what a greedy
// queue would do with the cheapest item anyway.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace visimp::detail {

/// T must have a `std::uint32_t key` member; Container is the buckets' vector type (the
/// engine's are huge-page backed once large: core/large_array.h).
template <class T, class Container = std::vector<T>>
class RadixHeap {
 public:
  bool empty() const { return size_ == 0; }
  std::size_t size() const { return size_; }

  void push(T item) {
    if (item.key < last_) item.key = last_;
    Container& bucket = buckets_[bucket_of(item.key)];
    // Grown by half, not doubled: doubling left the buckets of a 14M-face run holding 1.85×
    // their entries (300 MB unused at the parallel phase's peak). Each entry is then copied
    // ~2 times over its life instead of ~1, sequentially (by a quarter: ~4, and 7% wall).
    if (bucket.size() == bucket.capacity()) bucket.reserve(bucket.size() + bucket.size() / 2 + 64);
    bucket.push_back(item);
    ++size_;
  }

  /// Fills an empty heap with `items` at once, without the per-push growth: they wait in the
  /// top bucket, which the first pop sorts out with every bucket sized exactly. (Pushed one by
  /// one, 21M initial edges of a 14M-face mesh grew vectors by doubling and then moved into
  /// buckets that doubled again: over a gigabyte at the first pop.)
  void assign(Container&& items) {
    for (auto& bucket : buckets_) Container().swap(bucket);
    last_ = 0;
    size_ = items.size();
    buckets_.back() = std::move(items);
  }

  /// Removes and returns an item with the smallest key; among equal keys the last pushed.
  T pop() {
    if (buckets_[0].empty()) refill_first_bucket();
    T item = buckets_[0].back();
    buckets_[0].pop_back();
    --size_;
    return item;
  }

  /// The smallest key (the heap must not be empty).
  std::uint32_t min_key() {
    if (buckets_[0].empty()) refill_first_bucket();
    return last_;
  }

  /// Pops an item with the smallest key into `out` if that key is at most `limit`.
  bool pop_at_most(std::uint32_t limit, T& out) {
    if (size_ == 0) return false;
    if (buckets_[0].empty()) refill_first_bucket();
    if (last_ > limit) return false;  // bucket 0 holds exactly the keys equal to last_
    out = buckets_[0].back();
    buckets_[0].pop_back();
    --size_;
    return true;
  }

  /// Appends every item to `into` (bucket by bucket, in a fixed order) and empties the heap.
  void take_all(Container& into) {
    for (auto& bucket : buckets_) {
      into.insert(into.end(), bucket.begin(), bucket.end());
      Container().swap(bucket);
    }
    size_ = 0;
    last_ = 0;
  }

  /// Drops every item for which `drop(item)` is true (used to shed stale entries).
  template <class Pred>
  void remove_if(Pred drop) {
    size_ = 0;
    for (auto& bucket : buckets_) {
      std::size_t kept = 0;
      for (const T& item : bucket)
        if (!drop(item)) bucket[kept++] = item;
      bucket.resize(kept);
      bucket.shrink_to_fit();
      size_ += kept;
    }
  }

 private:
  int bucket_of(std::uint32_t key) const { return key == last_ ? 0 : 32 - __builtin_clz(key ^ last_); }

  void refill_first_bucket() {
    int i = 1;
    while (buckets_[i].empty()) ++i;
    std::uint32_t smallest = buckets_[i][0].key;
    for (const T& item : buckets_[i])
      if (item.key < smallest) smallest = item.key;
    last_ = smallest;
    std::array<std::size_t, 33> incoming{};
    for (const T& item : buckets_[i]) ++incoming[bucket_of(item.key)];
    for (int b = 0; b < i; ++b) buckets_[b].reserve(buckets_[b].size() + incoming[b]);
    for (const T& item : buckets_[i]) buckets_[bucket_of(item.key)].push_back(item);
    // A bucket once emptied refills slowly (it holds only keys far above the last popped):
    // give a large one's memory back instead of keeping capacity no one uses. Kept, the
    // emptied buckets' capacities added up to several times the live entries.
    if (buckets_[i].capacity() > kKeptCapacity)
      Container().swap(buckets_[i]);
    else
      buckets_[i].clear();
  }

  static constexpr std::size_t kKeptCapacity = 4096;

  std::array<Container, 33> buckets_;
  std::uint32_t last_ = 0;
  std::size_t size_ = 0;
};

/// The radix key of a non-negative float: its bit pattern, which orders like the value.
inline std::uint32_t radix_key(float cost) {
  std::uint32_t bits;
  static_assert(sizeof bits == sizeof cost);
  __builtin_memcpy(&bits, &cost, sizeof bits);
  return cost > 0 ? bits : 0;
}

}  // namespace visimp::detail
