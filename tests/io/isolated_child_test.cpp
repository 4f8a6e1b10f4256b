// run_in_child: what the child returns arrives intact, and every way it can fail (an exception,
// a crash, a limit, an early exit) is a ChildFailure with a reason, never the caller's end.
#include "isolated_child.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <new>
#include <string>
#include <vector>

namespace visimp::detail {
namespace {

std::string failure_of(const std::function<std::string()>& work, const ChildLimits& limits = {}) {
  try {
    run_in_child(work, limits);
  } catch (const ChildFailure& e) {
    return e.what();
  }
  ADD_FAILURE() << "the child succeeded";
  return {};
}

TEST(IsolatedChild, ALargeAnswerArrivesByteForByte) {
  std::string expected(8 << 20, '\0');  // far beyond a pipe's buffer
  for (std::size_t i = 0; i < expected.size(); ++i) expected[i] = char(i * 2654435761u >> 24);
  EXPECT_EQ(run_in_child([&] { return expected; }, {}), expected);
  EXPECT_EQ(run_in_child([] { return std::string(); }, {}), "");
}

TEST(IsolatedChild, TheChildsExceptionIsTheMessage) {
  EXPECT_EQ(failure_of([]() -> std::string { throw std::runtime_error("part.glb: bad accessor"); }),
            "part.glb: bad accessor");
}

TEST(IsolatedChild, ACrashIsNamedAndTheParentLivesOn) {
  EXPECT_NE(failure_of([]() -> std::string {
              ::raise(SIGSEGV);
              return "unreachable";
            }).find("crashed (signal 11"),
            std::string::npos);
  EXPECT_EQ(failure_of([]() -> std::string { _exit(7); }), "exited with code 7");
  EXPECT_EQ(run_in_child([] { return std::string("still here"); }, {}), "still here");
}

TEST(IsolatedChild, RunawayCpuTimeIsStopped) {
  ChildLimits limits;
  limits.cpu_seconds = 1;
  EXPECT_EQ(failure_of(
                []() -> std::string {
                  std::atomic<unsigned> spin{0};
                  for (;;) spin.fetch_add(1, std::memory_order_relaxed);
                },
                limits),
            "took more than 1 CPU seconds");
}

TEST(IsolatedChild, RunawayMemoryIsAnErrorNotTheMachinesProblem) {
  ChildLimits limits;
  limits.extra_memory = std::size_t(256) << 20;
  const std::string why = failure_of(
      []() -> std::string {
        std::vector<std::vector<char>> hog;
        for (;;) hog.emplace_back(std::size_t(64) << 20, 'x');
      },
      limits);
#if defined(__SANITIZE_ADDRESS__)
  EXPECT_FALSE(why.empty());  // ASan's allocator ends the child itself on a failed allocation
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
  EXPECT_FALSE(why.empty());
#else
  EXPECT_EQ(why, "ran out of memory (limit 256 MiB)");
#endif
#else
  EXPECT_EQ(why, "ran out of memory (limit 256 MiB)");
#endif
}

}  // namespace
}  // namespace visimp::detail
