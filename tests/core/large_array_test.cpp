// The engine's array allocator (lib/src/core/large_array.h): which arrays get a mapping of
// their own on a 2 MiB boundary (huge-page backed) and which come from operator new.
#include "large_array.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <numeric>
#include <vector>

namespace visimp::detail {
namespace {

bool on_huge_page_boundary(const void* p) { return reinterpret_cast<std::uintptr_t>(p) % kHugePageBytes == 0; }

template <class Array>
Array filled(std::size_t bytes) {
  Array a(bytes / sizeof(std::uint32_t));
  std::iota(a.begin(), a.end(), 0u);
  return a;
}

TEST(LargeArray, MapsArraysFromTheWholeHugePageSizeOnHugePageBoundaries) {
#if defined(__linux__)
  if (!huge_pages_on_4k()) GTEST_SKIP() << "pages are not 4 KiB: every array comes from operator new";
  const auto small = filled<LargeArray<std::uint32_t>>(kWholeHugePageBytes / 2);
  const auto smallest_whole = filled<LargeArray<std::uint32_t>>(kWholeHugePageBytes);
  const auto whole = filled<LargeArray<std::uint32_t>>(std::size_t(1) << 20);  // a D-sub-sized array
  const auto large = filled<LargeArray<std::uint32_t>>(kLargeArrayBytes + 4096);
  EXPECT_EQ(mapped_bytes<true>(small.size() * sizeof(std::uint32_t)), 0u);  // operator new's
  EXPECT_EQ(mapped_bytes<true>(smallest_whole.size() * sizeof(std::uint32_t)), kHugePageBytes);
  EXPECT_EQ(mapped_bytes<true>(whole.size() * sizeof(std::uint32_t)), kHugePageBytes);  // rounded up
  EXPECT_EQ(mapped_bytes<true>(kHugePageBytes + 1), 2 * kHugePageBytes);
  EXPECT_EQ(mapped_bytes<true>(kLargeArrayBytes + 1), kLargeArrayBytes + 1);  // not rounded: pages only
  EXPECT_TRUE(on_huge_page_boundary(smallest_whole.data()));
  EXPECT_TRUE(on_huge_page_boundary(whole.data()));
  EXPECT_TRUE(on_huge_page_boundary(large.data()));
  EXPECT_EQ(whole.back(), whole.size() - 1);
  EXPECT_EQ(large.back(), large.size() - 1);
#else
  GTEST_SKIP() << "huge-page mappings are Linux only";
#endif
}

TEST(LargeArray, GrowingArraysAreMappedOnlyFrom4MiB) {
#if defined(__linux__)
  if (!huge_pages_on_4k()) GTEST_SKIP() << "pages are not 4 KiB: every array comes from operator new";
  const auto medium = filled<GrowingArray<std::uint32_t>>(std::size_t(1) << 20);
  const auto large = filled<GrowingArray<std::uint32_t>>(kLargeArrayBytes + 4096);
  EXPECT_EQ(mapped_bytes<false>(medium.size() * sizeof(std::uint32_t)), 0u);  // operator new's
  EXPECT_EQ(mapped_bytes<false>(kLargeArrayBytes - 1), 0u);
  EXPECT_EQ(mapped_bytes<false>(kLargeArrayBytes), kLargeArrayBytes);
  EXPECT_TRUE(on_huge_page_boundary(large.data()));
#else
  GTEST_SKIP() << "huge-page mappings are Linux only";
#endif
}

// Growth through every size class: each reallocation frees the old array the way it was
// made (an unmap of the wrong length would leave pages behind or fault on the next use).
TEST(LargeArray, GrowsAndShrinksThroughEverySizeClass) {
  LargeArray<std::uint32_t> a;
  GrowingArray<std::uint32_t> g;
  for (std::uint32_t i = 0; i < (3u << 20); ++i) {
    a.push_back(i);
    g.push_back(i);
  }
  for (std::uint32_t i = 0; i < a.size(); i += 4099) ASSERT_EQ(a[i], i);
  a.resize(70000);
  a.shrink_to_fit();
  g.resize(70000);
  g.shrink_to_fit();
  EXPECT_EQ(a.back(), 69999u);
  EXPECT_EQ(g.back(), 69999u);
  LargeArray<std::uint32_t> copy = a;
  a.swap(copy);
  EXPECT_EQ(a, copy);
}

// A freed whole-huge-page array's mapping serves the next array of that length (a later
// simplify() call finds its arrays' pages resident), which starts value-initialized like any
// new vector; the cache holds at most kHeldBytes and unmaps the rest.
TEST(LargeArray, AFreedWholeHugePageServesTheNextArrayOfItsLength) {
#if defined(__linux__)
  if (!huge_pages_on_4k()) GTEST_SKIP() << "pages are not 4 KiB: every array comes from operator new";
  const std::size_t n = (std::size_t(1) << 20) / sizeof(std::uint32_t);  // 1 MiB: one whole huge page
  const std::uint32_t* first_data = nullptr;
  {
    LargeArray<std::uint32_t> first(n);
    std::iota(first.begin(), first.end(), 1u);  // leaves no zero behind
    first_data = first.data();
  }
  const LargeArray<std::uint32_t> second(n);
  EXPECT_EQ(second.data(), first_data);
  for (std::size_t i = 0; i < n; i += 1021) ASSERT_EQ(second[i], 0u) << i;
  EXPECT_EQ(second.back(), 0u);
  // More arrays than the cache holds, freed at once: it keeps exactly kHeldBytes (2 and 4 MiB
  // mappings fill it to the byte; the rest is unmapped), and each later array still works.
  {
    std::vector<LargeArray<std::uint32_t>> many;
    for (std::size_t k = 0; k < WholeHugePageCache::kHeldBytes / kHugePageBytes + 4; ++k) many.emplace_back(n, 7u);
  }
  EXPECT_EQ(WholeHugePageCache::instance().held_bytes(), WholeHugePageCache::kHeldBytes);
  std::vector<LargeArray<std::uint32_t>> again;
  for (int k = 0; k < 6; ++k) again.emplace_back(n, 3u);
  for (const auto& a : again) EXPECT_EQ(a[n / 2], 3u);
#else
  GTEST_SKIP() << "huge-page mappings are Linux only";
#endif
}

}  // namespace
}  // namespace visimp::detail

namespace visimp::detail {
namespace {

// Mesh's std::vectors (the PLY reader's positions and faces) are advised huge pages over the
// whole 2 MiB pages of their reserved, untouched capacity: never past either end.
TEST(AdviseHugePages, CoversOnlyTheWholeHugePagesInside) {
  constexpr std::uintptr_t MiB = std::uintptr_t(1) << 20;
  const AddressRange inside = huge_pages_inside(5 * MiB, 7 * MiB);  // [5, 12) MiB
  EXPECT_EQ(inside.first, 6 * MiB);
  EXPECT_EQ(inside.last, 12 * MiB);
  const AddressRange aligned = huge_pages_inside(4 * MiB, 4 * MiB);
  EXPECT_EQ(aligned.first, 4 * MiB);
  EXPECT_EQ(aligned.last, 8 * MiB);
  const AddressRange none = huge_pages_inside(5 * MiB, MiB);  // within one huge page
  EXPECT_LE(none.last, none.first);
}

TEST(AdviseHugePages, ReservesRoomForMoreAndKeepsWhatIsThere) {
  std::vector<std::uint64_t> v = {1, 2, 3};
  reserve_in_huge_pages(v, kLargeArrayBytes);  // 32 MiB of room: advised
  EXPECT_GE(v.capacity(), 3 + kLargeArrayBytes);
  EXPECT_EQ(v, (std::vector<std::uint64_t>{1, 2, 3}));
  const std::uint64_t* data = v.data();
  for (std::uint64_t i = 0; i < kLargeArrayBytes; ++i) v.push_back(i);  // no reallocation
  EXPECT_EQ(v.data(), data);
  EXPECT_EQ(v[3 + kLargeArrayBytes - 1], kLargeArrayBytes - 1);
}

}  // namespace
}  // namespace visimp::detail
