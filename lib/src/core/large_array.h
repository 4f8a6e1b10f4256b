// Private to the library: an allocator for arrays of megabytes, backed by transparent huge
// pages where the system offers them (docs/simplify.md, "Huge pages for the big arrays" and
// "Whole huge pages for a small mesh's arrays").
//
// The collapse engine's arrays (positions, quadrics, face lists, queues) are written once
// from start to end and then read all over. With 4 KiB pages every new array costs one page
// fault per 4 KiB: on the dragon at 10% about 50,000 of them, 13% of the run's samples on this
// project's virtual machines (a fault is an exit to the hypervisor). An array of at least
// kLargeArrayBytes is mapped on its own, starting on a 2 MiB boundary, and advised
// MADV_HUGEPAGE, so the kernel fills it 2 MiB at a time (Linux's default THP mode, "madvise",
// honours the advice; "never" ignores it and nothing changes). Its length is rounded to
// pages only: the last partial 2 MiB stays in small pages, so at most one huge page of an
// array's unused capacity can be resident. Freeing unmaps it at once, giving the memory back
// without malloc_trim.
//
// A LargeArray of kWholeHugePageBytes up to kLargeArrayBytes is mapped as whole huge pages
// (rounded up to 2 MiB): a small mesh's engine (the D-sub connector: 47k vertices, arrays of
// 0.4-2.3 MiB) otherwise took 4,000 faults, a fifth of its run. On this project's VMs a
// small-page fault costs ~10 µs and a whole 2 MiB huge page ~0.14 ms, so from 64 KiB (16
// faults) an array is cheaper in a huge page of its own. Freed, such a mapping is kept for the
// next array of its length (WholeHugePageCache): unmapped, it was faulted in again at every
// call, where malloc reuses what the last call freed. The rounding holds at most
// one huge page per array, under 4 MiB arrays only: it is for arrays used to their end. An
// array whose capacity runs ahead of its use (a reserved estimate, push_back growth) and of
// which there may be hundreds (the parallel phase's per-partition edges) is a GrowingArray:
// huge pages from kLargeArrayBytes only, as above.
//
// Smaller arrays, every array on a kernel whose pages are not 4 KiB (2 MiB huge pages go with
// 4 KiB pages on x86-64 and most ARM64 kernels) and every array off Linux come from operator
// new as usual.
#pragma once

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <new>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace visimp::detail {

constexpr std::size_t kLargeArrayBytes = std::size_t(4) << 20;
constexpr std::size_t kWholeHugePageBytes = std::size_t(64) << 10;  // docs/simplify.md, "Whole huge pages from 64 KiB"
constexpr std::size_t kHugePageBytes = std::size_t(2) << 20;

#if defined(__linux__)
// True where 2 MiB-aligned huge pages sit on 4 KiB pages; elsewhere (16 or 64 KiB pages) the
// rounding below would not be page-aligned, so large arrays come from operator new.
inline bool huge_pages_on_4k() {
  static const bool yes = sysconf(_SC_PAGESIZE) == 4096;
  return yes;
}

inline void* map_large_array(std::size_t bytes) {
  constexpr std::size_t kHuge = kHugePageBytes, kPage = 4096;
  const std::size_t length = (bytes + kPage - 1) & ~(kPage - 1);
  // Over-map by 2 MiB and trim, so the array starts on a huge-page boundary.
  void* raw = mmap(nullptr, length + kHuge, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (raw == MAP_FAILED) throw std::bad_alloc();
  const auto start = reinterpret_cast<std::uintptr_t>(raw);
  const std::uintptr_t aligned = (start + kHuge - 1) & ~std::uintptr_t(kHuge - 1);
  if (aligned > start) munmap(raw, aligned - start);
  const std::uintptr_t end = start + length + kHuge;
  if (end > aligned + length) munmap(reinterpret_cast<void*>(aligned + length), end - (aligned + length));
  madvise(reinterpret_cast<void*>(aligned), length, MADV_HUGEPAGE);  // advice: failure changes nothing
  return reinterpret_cast<void*>(aligned);
}

inline void unmap_large_array(void* p, std::size_t bytes) {
  constexpr std::size_t kPage = 4096;
  munmap(p, (bytes + kPage - 1) & ~(kPage - 1));
}

// Freed whole-huge-page mappings (2 or 4 MiB), kept for the
// next array of the same length instead of unmapped: an unmapped array is faulted in again at
// the next call, where malloc hands a later call what the last one freed (a small mesh's
// arrays in a loop of simplify() calls). At most kHeldBytes are held; the rest is unmapped.
// The memory comes back as it was left (a std::vector writes every element it creates).
class WholeHugePageCache {
 public:
  static constexpr std::size_t kHeldBytes = std::size_t(32) << 20;

  static WholeHugePageCache& instance() {
    // Never destroyed: an array freed during static destruction still finds it.
    static WholeHugePageCache* const cache = new WholeHugePageCache;
    return *cache;
  }

  // The mappings it takes: whole huge pages up to kLargeArrayBytes.
  static bool holds_length(std::size_t mapped) { return mapped <= kLargeArrayBytes && mapped % kHugePageBytes == 0; }

  void* take(std::size_t bytes) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (std::size_t i = held_.size(); i-- > 0;)
      if (held_[i].bytes == bytes) {
        void* p = held_[i].data;
        held_.erase(held_.begin() + static_cast<std::ptrdiff_t>(i));
        held_bytes_ -= bytes;
        return p;
      }
    return nullptr;
  }

  // False when full: the caller unmaps. Called from noexcept deallocate(): held_ never grows
  // here (every mapping is at least 2 MiB, so kHeldBytes fit in the room the constructor reserved).
  bool keep(void* p, std::size_t bytes) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (held_bytes_ + bytes > kHeldBytes) return false;
    held_.push_back({p, bytes});
    held_bytes_ += bytes;
    return true;
  }

  // What it holds now (tests check the bound).
  std::size_t held_bytes() {
    std::lock_guard<std::mutex> lock(mutex_);
    return held_bytes_;
  }

 private:
  WholeHugePageCache() { held_.reserve(kHeldBytes / kHugePageBytes); }

  struct Held {
    void* data;
    std::size_t bytes;
  };
  std::mutex mutex_;
  std::vector<Held> held_;
  std::size_t held_bytes_ = 0;
};
#endif

// Advises MADV_HUGEPAGE for the whole 2 MiB pages inside [data, data + bytes), from
// kLargeArrayBytes: for a std::vector whose capacity was just reserved and not yet written
// (Mesh's arrays come from std::allocator: glibc maps such blocks on their own, or — once its
// mmap threshold has grown after a large block was freed — hands out heap, advised the same). Reading
// the 14M-face mesh wrote 334 MB of positions and faces through ~82,000 small-page faults.
// Advice only: memory already touched, or a kernel in THP mode "never", is left as it is.
// The whole 2 MiB pages inside [start, start + bytes): [first, last), empty when last <= first.
struct AddressRange {
  std::uintptr_t first, last;
};
inline AddressRange huge_pages_inside(std::uintptr_t start, std::size_t bytes) {
  const std::uintptr_t mask = ~std::uintptr_t(kHugePageBytes - 1);
  return {(start + kHugePageBytes - 1) & mask, (start + bytes) & mask};
}

inline void advise_huge_pages(const void* data, std::size_t bytes) {
#if defined(__linux__)
  if (bytes < kLargeArrayBytes || !huge_pages_on_4k()) return;
  const AddressRange pages = huge_pages_inside(reinterpret_cast<std::uintptr_t>(data), bytes);
  if (pages.last > pages.first) madvise(reinterpret_cast<void*>(pages.first), pages.last - pages.first, MADV_HUGEPAGE);
#else
  (void)data;
  (void)bytes;
#endif
}

// Reserves room for n more elements of a vector and advises huge pages for it (above).
template <class Vector>
void reserve_in_huge_pages(Vector& v, std::size_t n) {
  v.reserve(v.size() + n);
  advise_huge_pages(v.data() + v.size(), n * sizeof(typename Vector::value_type));
}

// The bytes mapped for an array of `bytes` (0: operator new's).
template <bool kWholeHugePages>
std::size_t mapped_bytes(std::size_t bytes) {
#if defined(__linux__)
  if (!huge_pages_on_4k()) return 0;
  if (bytes >= kLargeArrayBytes) return bytes;
  if (kWholeHugePages && bytes >= kWholeHugePageBytes) return (bytes + kHugePageBytes - 1) & ~(kHugePageBytes - 1);
#endif
  (void)bytes;
  return 0;
}

template <class T, bool kWholeHugePages>
struct LargeArrayAllocator {
  using value_type = T;
  template <class U>
  struct rebind {
    using other = LargeArrayAllocator<U, kWholeHugePages>;
  };
  static_assert(alignof(T) <= __STDCPP_DEFAULT_NEW_ALIGNMENT__, "operator new(bytes) aligns no further");

  LargeArrayAllocator() = default;
  template <class U>
  LargeArrayAllocator(const LargeArrayAllocator<U, kWholeHugePages>&) noexcept {}

  T* allocate(std::size_t n) {
    if (n > SIZE_MAX / sizeof(T)) throw std::bad_array_new_length();
#if defined(__linux__)
    if (const std::size_t mapped = mapped_bytes<kWholeHugePages>(n * sizeof(T))) {
      if (WholeHugePageCache::holds_length(mapped))
        if (void* reused = WholeHugePageCache::instance().take(mapped)) return static_cast<T*>(reused);
      return static_cast<T*>(map_large_array(mapped));
    }
#endif
    return static_cast<T*>(::operator new(n * sizeof(T)));
  }

  void deallocate(T* p, std::size_t n) noexcept {
#if defined(__linux__)
    if (const std::size_t mapped = mapped_bytes<kWholeHugePages>(n * sizeof(T))) {
      if (WholeHugePageCache::holds_length(mapped) && WholeHugePageCache::instance().keep(p, mapped)) return;
      return unmap_large_array(p, mapped);
    }
#endif
    ::operator delete(p);
  }

  template <class U>
  bool operator==(const LargeArrayAllocator<U, kWholeHugePages>&) const noexcept {
    return true;
  }
  template <class U>
  bool operator!=(const LargeArrayAllocator<U, kWholeHugePages>&) const noexcept {
    return false;
  }
};

/// A std::vector for an array used to its end: huge-page backed from kWholeHugePageBytes
/// (whole huge pages below kLargeArrayBytes).
template <class T>
using LargeArray = std::vector<T, LargeArrayAllocator<T, true>>;

/// A std::vector whose capacity may run ahead of its use: huge-page backed from
/// kLargeArrayBytes, never rounded up.
template <class T>
using GrowingArray = std::vector<T, LargeArrayAllocator<T, false>>;

}  // namespace visimp::detail
