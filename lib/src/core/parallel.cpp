#include "visimp/core/parallel.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace visimp {

unsigned worker_count(unsigned threads, std::size_t jobs) {
  unsigned n = threads != 0 ? threads : std::max(1u, std::thread::hardware_concurrency());
  return static_cast<unsigned>(std::max<std::size_t>(1, std::min<std::size_t>(n, jobs)));
}

void parallel_for(std::size_t first, std::size_t last, unsigned workers,
                  const std::function<void(unsigned worker, std::size_t item)>& job,
                  const std::function<void(double done)>& progress) {
  if (first >= last) return;
  std::atomic<std::size_t> next{first};
  std::atomic<std::size_t> done{0};
  std::atomic<bool> failed{false};
  std::exception_ptr error;
  std::mutex mutex;
  std::condition_variable finished;
  auto work = [&](unsigned worker) {
    try {
      for (std::size_t item; !failed && (item = next++) < last;) {
        job(worker, item);
        ++done;
      }
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex);
      if (!error) error = std::current_exception();
      failed = true;
    }
    std::lock_guard<std::mutex> lock(mutex);
    finished.notify_all();
  };
  std::vector<std::thread> threads;
  for (unsigned w = 1; w < workers; ++w) threads.emplace_back(work, w);
  if (!progress) {
    work(0);
  } else {
    // Worker 0 runs on its own thread too, so this thread is free to report progress.
    threads.emplace_back(work, 0u);
    const std::size_t total = last - first;
    std::unique_lock<std::mutex> lock(mutex);
    while (done < total && !failed) {
      finished.wait_for(lock, std::chrono::milliseconds(100));
      // A progress callback may throw to cancel (the Python module does on Ctrl-C): stop the
      // workers and rethrow after joining them, as for a failing job.
      try {
        progress(static_cast<double>(done) / static_cast<double>(total));
      } catch (...) {
        if (!error) error = std::current_exception();
        failed = true;
      }
    }
  }
  for (std::thread& t : threads) t.join();
  if (error) std::rethrow_exception(error);
}

void parallel_ranges(std::size_t n, std::size_t chunk, unsigned workers,
                     const std::function<void(std::size_t begin, std::size_t end)>& job) {
  chunk = std::max<std::size_t>(chunk, 1);
  const std::size_t ranges = (n + chunk - 1) / chunk;
  if (ranges <= 1 || workers <= 1) {  // no thread to start: run inline, in order
    for (std::size_t r = 0; r < ranges; ++r) job(r * chunk, std::min(n, (r + 1) * chunk));
    return;
  }
  parallel_for(0, ranges, static_cast<unsigned>(std::min<std::size_t>(workers, ranges)),
               [&](unsigned, std::size_t r) { job(r * chunk, std::min(n, (r + 1) * chunk)); });
}

}  // namespace visimp
