// The worker pool: every item runs once, a failing job stops the run, and a progress callback
// that throws cancels it (the Python module's Ctrl-C) instead of terminating the process.
#include "visimp/core/parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

namespace visimp {
namespace {

TEST(Parallel, EveryItemRunsExactlyOnce) {
  std::vector<std::atomic<int>> runs(1000);
  parallel_for(0, runs.size(), 2, [&](unsigned, std::size_t item) { ++runs[item]; });
  for (const auto& r : runs) EXPECT_EQ(r.load(), 1);
}

// Ranges are cut the same whatever the thread count (per-item outputs then match), cover
// every item once, and a short last range ends at n.
TEST(Parallel, RangesCoverEveryItemOnceAndDoNotDependOnThreads) {
  for (const unsigned workers : {1u, 3u}) {
    std::vector<std::atomic<int>> hits(1000);
    std::vector<std::atomic<std::size_t>> range_end(1000);
    parallel_ranges(hits.size(), 64, workers, [&](std::size_t begin, std::size_t end) {
      range_end[begin] = end;
      for (std::size_t i = begin; i < end; ++i) ++hits[i];
    });
    for (std::size_t i = 0; i < hits.size(); ++i) {
      ASSERT_EQ(hits[i], 1) << "item " << i << ", " << workers << " workers";
      if (i % 64 == 0) {
        EXPECT_EQ(range_end[i], std::min<std::size_t>(i + 64, 1000));
      }
    }
  }
  bool ran = false;
  parallel_ranges(0, 64, 3, [&](std::size_t, std::size_t) { ran = true; });
  EXPECT_FALSE(ran);
}

TEST(Parallel, AFailingJobIsRethrownOnTheCaller) {
  EXPECT_THROW(parallel_for(0, 100, 2,
                            [](unsigned, std::size_t item) {
                              if (item == 7) throw std::runtime_error("item 7");
                            }),
               std::runtime_error);
}

TEST(Parallel, AThrowingProgressCallbackCancelsTheRun) {
  struct Cancelled {};
  std::atomic<std::size_t> ran{0};
  const std::size_t items = 100'000;  // 1 ms each: far longer than the first report (100 ms)
  EXPECT_THROW(parallel_for(
                   0, items, 2,
                   [&](unsigned, std::size_t) {
                     std::this_thread::sleep_for(std::chrono::milliseconds(1));
                     ++ran;
                   },
                   [](double) { throw Cancelled{}; }),
               Cancelled);
  EXPECT_LT(ran.load(), items / 10);
}

}  // namespace
}  // namespace visimp
