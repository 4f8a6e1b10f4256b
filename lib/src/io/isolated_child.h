// Runs a piece of work in a forked child process, so that a library we cannot harden (assimp:
// Debian's build crashes, runs out of memory or leaks on malformed scene files within seconds of
// fuzzing) cannot take the calling process down with it. The child gets a memory (data segment)
// and a CPU-time limit, sends its result through a pipe and ends with _exit; the parent turns every
// way the child can end (an exception's message, a signal, a limit, a torn pipe) into one
// ChildFailure with a one-line reason.
#pragma once

#include <cstddef>
#include <functional>
#include <stdexcept>
#include <string>

namespace visimp::detail {

struct ChildLimits {
  std::size_t extra_memory = std::size_t(4) << 30;  ///< data-segment bytes beyond what the parent has already
  unsigned cpu_seconds = 600;
};

class ChildFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The bytes `work` returned in the child. Throws ChildFailure when the child threw (its
/// message), was killed (the signal's name), or exited without a complete answer.
std::string run_in_child(const std::function<std::string()>& work, const ChildLimits& limits);

}  // namespace visimp::detail
