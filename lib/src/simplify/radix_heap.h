// Private to simplify: a radix heap (Ahuja, Mehlhorn, Orlin & Tarjan 1990) over 32-bit keys.
//
// Collapse costs are non-negative floats, whose IEEE bit patterns order like unsigned
// integers, and the queue is (almost) monotone: merged quadrics only grow, so a new cost is
// rarely below the last one popped. A radix heap exploits that: push is O(1) and a pop moves
// items only towards the smallest key, all with sequential memory access — on a million-edge
// mesh this is several times faster than a binary heap, whose sifts miss cache.
// A key below the last popped key is clamped to it ("process next"), which is what a greedy
// queue would do with the cheapest item anyway.
//
// Keys are split into digits of 1 or 8 bits: a key's level is the digit in which it
// first differs from the last popped key, its bucket that digit's value. With 8-bit digits an
// item moves at most three times before it is popped (level 3 to 0), where the textbook heap
// with one bucket per bit (1-bit digits) moved each item ~11 times (the D-sub at 1%: a refill
// per pop, a fifth of the run's instructions). A level-0 bucket holds a single key, so the
// next key up is found by a bit scan without moving anything. But every non-empty bucket holds
// a block, and wide digits keep hundreds of buckets non-empty: the parallel phase's hundreds of
// small queues at 14M faces took 1.6x as long with 8-bit digits (allocator churn and pages),
// so they keep 1-bit digits and the one serial queue takes 8 (simplify.cpp). The pop order is
// a function of the pushes alone (the smallest key, and among equal keys the last pushed),
// whatever the digits: equal keys always share a bucket, in the order pushed.
//
// Each bucket is a chain of fixed-size blocks (4 KiB; 1 KiB under 8-bit digits), not a
// growing array: a bucket never copies its items to grow, and the blocks a refill empties are
// refilled at once by the buckets it fills, so the memory stays mapped and in cache. (Growing
// arrays copied every entry about twice and faulted in fresh pages for each copy: 8% of a run
// on the dragon.) Each non-empty bucket wastes at most one part-filled block.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <new>
#include <type_traits>
#include <utility>

namespace visimp::detail {

/// T must be trivially copyable with a `std::uint32_t key` member. Container (a vector of T)
/// is what assign() takes and take_all() fills. kDigitBits: 1 or 8 (wider: fewer moves per
/// item, more blocks held; see above).
template <class T, class Container, int kDigitBits = 1>
class RadixHeap {
  static_assert(std::is_trivially_copyable_v<T>);
  static_assert(kDigitBits == 1 || kDigitBits == 8);

 public:
  RadixHeap() = default;
  RadixHeap(const RadixHeap& other) : bulk_(other.bulk_), last_(other.last_), size_(other.size_) {
    for (std::size_t b = 0; b < buckets_.size(); ++b)
      for (const Block* block = other.buckets_[b].oldest; block != nullptr; block = block->newer)
        for (std::uint32_t i = 0; i < block->count; ++i) append(static_cast<int>(b), block->items()[i]);
  }
  RadixHeap(RadixHeap&& other) noexcept { swap(other); }
  RadixHeap& operator=(RadixHeap other) noexcept {
    swap(other);
    return *this;
  }
  ~RadixHeap() {
    clear();
    release_spare_blocks(0);
  }

  bool empty() const { return size_ == 0; }
  std::size_t size() const { return size_; }

  void push(T item) {
    if (!bulk_.empty()) spread_bulk();
    if (item.key < last_) item.key = last_;
    append(bucket_of(item.key), item);
    ++size_;
  }

  /// Empties the heap and fills it with `items` at once: they wait in their array until the
  /// next push or pop spreads them over the buckets. (Pushed one by one, the initial edges
  /// would be copied into the top bucket only to be moved down at the first pop.)
  void assign(Container&& items) {
    clear();
    size_ = items.size();
    bulk_ = std::move(items);
  }

  /// assign() and the spreading that would follow at the next push or pop, at once, from any
  /// array of T (the array is left as it is): a heap filled from a scratch array that is then
  /// freed.
  template <class Items>
  void assign_spread(const Items& items) {
    clear();
    size_ = items.size();
    if (size_ != 0) spread(items);
  }

  /// Removes and returns an item with the smallest key; among equal keys the last pushed.
  T pop() {
    if (buckets_[current()].newest == nullptr) advance();
    --size_;
    return take_first();
  }

  /// The smallest key (the heap must not be empty).
  std::uint32_t min_key() {
    if (buckets_[current()].newest == nullptr) advance();
    return last_;
  }

  /// Pops an item with the smallest key into `out` if that key is at most `limit`.
  bool pop_at_most(std::uint32_t limit, T& out) {
    if (size_ == 0) return false;
    if (buckets_[current()].newest == nullptr) advance();
    if (last_ > limit) return false;  // the current bucket holds exactly the keys equal to last_
    out = take_first();
    --size_;
    return true;
  }

  /// Appends every item to `into` (bucket by bucket, oldest first: equal keys in the order
  /// pushed) and empties the heap.
  void take_all(Container& into) {
    into.insert(into.end(), bulk_.begin(), bulk_.end());  // when there is bulk, no bucket has items
    for (const Bucket& bucket : buckets_)
      for (const Block* block = bucket.oldest; block != nullptr; block = block->newer)
        into.insert(into.end(), block->items(), block->items() + block->count);
    clear();
    release_spare_blocks(0);
  }

  /// Drops every item for which `drop(item)` is true (used to shed stale entries), keeping the
  /// others' order; the blocks left empty are freed.
  template <class Pred>
  void remove_if(Pred drop) {
    size_ = 0;
    std::size_t kept = 0;
    for (const T& item : bulk_)
      if (!drop(item)) bulk_[kept++] = item;
    bulk_.resize(kept);
    bulk_.shrink_to_fit();
    size_ += kept;
    for (Bucket& bucket : buckets_) {
      // Compact in place: a write cursor follows the read cursor through the chain.
      Block* write = bucket.oldest;
      std::uint32_t at = 0;
      for (Block* read = bucket.oldest; read != nullptr; read = read->newer) {
        for (std::uint32_t i = 0; i < read->count; ++i) {
          if (drop(read->items()[i])) continue;
          if (at == kBlockItems) {
            write = write->newer;
            at = 0;
          }
          put(write, at++, read->items()[i]);
          ++size_;
        }
      }
      if (write == nullptr) continue;
      Block* rest = write->newer;
      write->count = at;
      write->newer = nullptr;
      bucket.newest = write;
      if (at == 0) {  // nothing kept in the bucket's first block either
        bucket.oldest = bucket.newest = nullptr;
        mark_empty(static_cast<int>(&bucket - buckets_.data()));
        give_back(write);
      }
      while (rest != nullptr) {
        Block* next = rest->newer;
        give_back(rest);
        rest = next;
      }
    }
  }

 private:
  // A block: this header, then its items up to kBlockBytes (1 KiB under 8-bit digits, whose
  // hundreds of non-empty buckets each hold a part-filled block; 4 KiB otherwise).
  struct Block {
    Block* older;
    Block* newer;
    std::uint32_t count;
    T* items() { return reinterpret_cast<T*>(reinterpret_cast<unsigned char*>(this) + kItemsOffset); }
    const T* items() const {
      return reinterpret_cast<const T*>(reinterpret_cast<const unsigned char*>(this) + kItemsOffset);
    }
  };
  static constexpr std::size_t kItemsOffset = (sizeof(Block) + alignof(T) - 1) / alignof(T) * alignof(T);
  static constexpr std::size_t kBlockBytes = kDigitBits >= 8 ? 1024 : 4096;
  static constexpr std::uint32_t kBlockItems = static_cast<std::uint32_t>((kBlockBytes - kItemsOffset) / sizeof(T));
  static_assert(kBlockItems >= 16, "items too large for a block");
  // Copies an item into a block's slot (an object created there, not assigned over raw memory).
  static void put(Block* block, std::uint32_t slot, const T& item) { new (block->items() + slot) T(item); }
  struct Bucket {
    Block* oldest = nullptr;
    Block* newest = nullptr;
  };
  // Emptied blocks kept for reuse, beyond them freed: a refill hands its blocks over one by
  // one, and a lane of the parallel phase should hold little it does not use. Byte digits
  // empty and refill buckets of a few items at every few pops: with four spares the allocator
  // took 6% of the D-sub's run at 1%, with 512 (the one serial queue's) under 1%.
  static constexpr std::size_t kSpareLimit = kDigitBits >= 8 ? 512 : 4;

  static constexpr std::uint32_t kDigitMask = (1u << kDigitBits) - 1;
  static constexpr int kBuckets = kDigitBits == 1 ? 33 : 4 << 8;  // bits: last_ and 32; bytes: 4 levels x 256
  static constexpr int kWords = (kBuckets + 63) / 64;
  static_assert(kWords <= 64, "one summary bit per word of the bucket mask");

  // Bytes: the level (the highest byte in which key differs from last_) times 256, plus key's
  // byte there. Bits: the textbook layout (bucket 0: last_; bucket i: keys whose highest bit
  // unlike last_'s is bit i - 1). Either way bucket indices order like the keys they hold, and
  // last_ itself is in bucket current().
  int bucket_of(std::uint32_t key) const {
    const std::uint32_t differs = key ^ last_;
    if constexpr (kDigitBits == 1) {
      return differs == 0 ? 0 : 32 - __builtin_clz(differs);
    } else {
      const int level = (31 - __builtin_clz(differs | 1u)) / 8;  // differs == 0: level 0, no branch
      return (level << 8) | static_cast<int>((key >> (level * 8)) & kDigitMask);
    }
  }
  int current() const { return kDigitBits == 1 ? 0 : static_cast<int>(last_ & kDigitMask); }

  void mark_nonempty(int b) {
    nonempty_[b >> 6] |= std::uint64_t(1) << (b & 63);
    nonempty_words_ |= std::uint64_t(1) << (b >> 6);
  }
  void mark_empty(int b) {
    nonempty_[b >> 6] &= ~(std::uint64_t(1) << (b & 63));
    if (nonempty_[b >> 6] == 0) nonempty_words_ &= ~(std::uint64_t(1) << (b >> 6));
  }
  // The lowest non-empty bucket (the heap must hold an item outside the bulk).
  int lowest_nonempty() const {
    const int w = __builtin_ctzll(nonempty_words_);
    return (w << 6) | __builtin_ctzll(nonempty_[w]);
  }

  void append(int b, const T& item) {
    Bucket& bucket = buckets_[b];
    Block* block = bucket.newest;
    if (block == nullptr || block->count == kBlockItems) {
      if (block == nullptr) mark_nonempty(b);
      Block* fresh = new_block();
      fresh->older = block;
      fresh->newer = nullptr;
      fresh->count = 0;
      if (block != nullptr)
        block->newer = fresh;
      else
        bucket.oldest = fresh;
      bucket.newest = block = fresh;
    }
    put(block, block->count++, item);
  }

  // The newest item of the current bucket (the smallest key, last pushed among equals).
  T take_first() {
    const int b = current();
    Bucket& bucket = buckets_[b];
    Block* block = bucket.newest;
    const T item = block->items()[--block->count];
    if (block->count == 0) {
      bucket.newest = block->older;
      if (bucket.newest != nullptr) {
        bucket.newest->newer = nullptr;
      } else {
        bucket.oldest = nullptr;
        mark_empty(b);
      }
      give_back(block);
    }
    return item;
  }

  // Makes last_ the smallest key queued (the current bucket is empty, the heap is not).
  void advance() {
    if (!bulk_.empty()) return spread_bulk();
    const int i = lowest_nonempty();
    if (kDigitBits != 1 && i <= static_cast<int>(kDigitMask)) {  // level 0: one key, now current()
      last_ = (last_ & ~kDigitMask) | static_cast<std::uint32_t>(i);
      return;
    }
    std::uint32_t smallest = UINT32_MAX;
    for (const Block* block = buckets_[i].oldest; block != nullptr; block = block->newer)
      for (std::uint32_t k = 0; k < block->count; ++k) smallest = std::min(smallest, block->items()[k].key);
    last_ = smallest;
    // Every item goes to a lower level, oldest first; each emptied block is reused at once.
    Block* block = buckets_[i].oldest;
    buckets_[i] = Bucket{};
    mark_empty(i);
    while (block != nullptr) {
      for (std::uint32_t k = 0; k < block->count; ++k) append(bucket_of(block->items()[k].key), block->items()[k]);
      Block* next = block->newer;
      give_back(block);
      block = next;
    }
  }

  // The assigned items over the buckets (all empty while there is bulk), from their smallest
  // key up: what a refill of a top bucket holding them would do. The array becomes the slab:
  // blocks are carved from the part already read, so the spread touches little fresh memory
  // (on this project's VMs a first touch of a page costs ~10 µs, and fresh blocks were four
  // in five of the D-sub's page faults in simplify()), and at 14M faces the serial queue's
  // blocks no longer come on top of the array they are spread from.
  void spread_bulk() {
    slab_.swap(bulk_);  // bulk_ takes the slab's place, empty since clear() before the assignment
    std::uint32_t smallest = UINT32_MAX;
    for (const T& item : slab_) smallest = std::min(smallest, item.key);
    last_ = smallest;
    for (std::size_t i = 0; i < slab_.size(); ++i) {
      const T item = slab_[i];  // a copy: the block carved next may cover its slot
      slab_read_ = i + 1;
      append(bucket_of(item.key), item);
    }
  }

  template <class Items>
  void spread(const Items& items) {
    std::uint32_t smallest = UINT32_MAX;
    for (const T& item : items) smallest = std::min(smallest, item.key);
    last_ = smallest;
    for (const T& item : items) append(bucket_of(item.key), item);
  }

  Block* new_block() {
    if (slab_free_ != nullptr) {
      Block* block = slab_free_;
      slab_free_ = block->newer;
      return block;
    }
    if ((slab_carved_ + 1) * kBlockBytes <= slab_read_ * sizeof(T)) {
      unsigned char* at = reinterpret_cast<unsigned char*>(slab_.data()) + slab_carved_++ * kBlockBytes;
      return new (at) Block;
    }
    if (spare_ == nullptr) return new (::operator new(kBlockBytes)) Block;
    Block* block = spare_;
    spare_ = block->newer;
    --spare_count_;
    return block;
  }

  bool in_slab(const Block* block) const {
    const auto at = reinterpret_cast<std::uintptr_t>(block), begin = reinterpret_cast<std::uintptr_t>(slab_.data());
    return at >= begin && at < begin + slab_carved_ * kBlockBytes;
  }

  void give_back(Block* block) {
    if (in_slab(block)) {  // freed with the slab
      block->newer = slab_free_;
      slab_free_ = block;
      return;
    }
    if (spare_count_ >= kSpareLimit) {
      ::operator delete(block);
      return;
    }
    block->newer = spare_;
    spare_ = block;
    ++spare_count_;
  }

  void release_spare_blocks(std::size_t keep) {
    while (spare_count_ > keep) {
      Block* block = spare_;
      spare_ = block->newer;
      --spare_count_;
      ::operator delete(block);
    }
  }

  // Empties the heap; its blocks become spares.
  void clear() {
    for (Bucket& bucket : buckets_) {
      for (Block* block = bucket.oldest; block != nullptr;) {
        Block* next = block->newer;
        give_back(block);
        block = next;
      }
      bucket = Bucket{};
    }
    nonempty_ = {};
    nonempty_words_ = 0;
    Container().swap(bulk_);
    Container().swap(slab_);  // every block carved from it was given back above
    slab_read_ = slab_carved_ = 0;
    slab_free_ = nullptr;
    last_ = 0;
    size_ = 0;
  }

  void swap(RadixHeap& other) noexcept {
    std::swap(buckets_, other.buckets_);
    std::swap(nonempty_, other.nonempty_);
    std::swap(nonempty_words_, other.nonempty_words_);
    bulk_.swap(other.bulk_);
    std::swap(last_, other.last_);
    std::swap(size_, other.size_);
    std::swap(spare_, other.spare_);
    std::swap(spare_count_, other.spare_count_);
    slab_.swap(other.slab_);  // a vector's swap keeps its elements (and the blocks in them) in place
    std::swap(slab_read_, other.slab_read_);
    std::swap(slab_carved_, other.slab_carved_);
    std::swap(slab_free_, other.slab_free_);
  }

  std::array<Bucket, kBuckets> buckets_{};
  std::array<std::uint64_t, kWords> nonempty_{};  // bit b: buckets_[b] holds items
  std::uint64_t nonempty_words_ = 0;               // bit w: nonempty_[w] != 0
  Container bulk_;  // items given by assign(), not yet spread
  std::uint32_t last_ = 0;
  std::size_t size_ = 0;
  Block* spare_ = nullptr;  // emptied blocks for reuse, chained through `newer`
  std::size_t spare_count_ = 0;
  // The spread bulk array: blocks are carved from its items already read (spread_bulk).
  Container slab_;
  std::size_t slab_read_ = 0;    // items of slab_ read: the carving stays below them
  std::size_t slab_carved_ = 0;  // blocks carved from the front of slab_
  Block* slab_free_ = nullptr;   // carved blocks emptied, for reuse, chained through `newer`
};

/// The radix key of a non-negative float: its bit pattern, which orders like the value.
inline std::uint32_t radix_key(float cost) {
  std::uint32_t bits;
  static_assert(sizeof bits == sizeof cost);
  __builtin_memcpy(&bits, &cost, sizeof bits);
  return cost > 0 ? bits : 0;
}

}  // namespace visimp::detail
