// The one worker pool: items taken in turn by a fixed number of threads (dynamic balance),
// the first exception stops the others and is rethrown on the caller. Results must not depend
// on which worker ran an item — callers write per-item outputs and reduce them in item order.
#pragma once

#include <cstddef>
#include <functional>

namespace visimp {

/// Number of workers for `threads` (0 = hardware concurrency), never more than `jobs`.
unsigned worker_count(unsigned threads, std::size_t jobs);

/// Runs `job(worker, item)` for items [first, last) on `workers` threads. When `progress` is
/// set, the calling thread reports the finished share (0..1) to it about ten times a second;
/// if it throws, the workers stop after their current item and the exception is rethrown
/// (how a front end cancels a long run).
void parallel_for(std::size_t first, std::size_t last, unsigned workers,
                  const std::function<void(unsigned worker, std::size_t item)>& job,
                  const std::function<void(double done)>& progress = {});

/// Runs `job(begin, end)` over [0, n) cut into ranges of `chunk` items, on `workers` threads:
/// for loops whose body is too cheap for a call per item. The ranges do not depend on
/// `workers`, so a job that writes per-item outputs gives the same bytes for any thread count.
void parallel_ranges(std::size_t n, std::size_t chunk, unsigned workers,
                     const std::function<void(std::size_t begin, std::size_t end)>& job);

}  // namespace visimp
