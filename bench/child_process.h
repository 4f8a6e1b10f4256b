// Runs one benchmarked method in a forked child so its CPU time and peak memory are its
// own: CPU is the child's process CPU clock around the call; memory is the child's peak RSS
// (VmHWM, reset at fork) minus its RSS at fork, after handing freed heap pages back.
#pragma once

#include <fcntl.h>
#include <malloc.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

namespace bench {

inline long rss_kb() {
  std::ifstream statm("/proc/self/statm");
  long size = 0, resident = 0;
  statm >> size >> resident;
  return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

// Peak RSS since the last reset_peak_rss() (a forked child inherits its parent's peak).
inline long peak_rss_kb() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::stol(line.substr(6));
  return 0;
}

inline void reset_peak_rss() { std::ofstream("/proc/self/clear_refs") << "5"; }

inline double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

inline double wall_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// A file's bytes ("" when it cannot be read): for "the same output" checks.
inline std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

struct ChildResult {
  bool ok = false;
  double cpu = 0, wall = 0, peak_mb = 0;
  std::vector<double> values;  ///< what the method reported
};

/// Runs `method` in a child; it returns `count` numbers of its own (stage times, results).
/// A child past `cpu_limit_seconds` of CPU is killed and reported as failed, so a peer that
/// never returns on some input (CGAL's edge_collapse on non-manifold meshes) cannot stall the
/// whole run. The parent enforces the limit by reading the child's CPU clock: an RLIMIT_CPU in
/// the child arms the kernel's process CPU timer, and with it armed (Linux 6.18 here) the
/// child's own CPU clock and getrusage advance in ticks, so a 3 ms run read 0 to 3 ms.
inline ChildResult run_in_child(std::size_t count, const std::function<std::vector<double>()>& method,
                                double cpu_limit_seconds = 300) {
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) return {};
  std::fflush(nullptr);  // or the child inherits unwritten output and may write it again
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    malloc_trim(0);  // hand freed heap pages back, or the method reuses them unseen by RSS
    reset_peak_rss();
    const long base = rss_kb();
    const double c0 = cpu_seconds(), w0 = wall_seconds();
    std::vector<double> values = method();
    values.resize(count);
    values.push_back(cpu_seconds() - c0);
    values.push_back(wall_seconds() - w0);
    values.push_back(double(peak_rss_kb() - base) / 1024.0);
    const auto bytes = static_cast<ssize_t>(values.size() * sizeof(double));
    if (write(fds[1], values.data(), static_cast<std::size_t>(bytes)) != bytes) _exit(1);
    _exit(0);
  }
  close(fds[1]);
  if (pid < 0) {
    close(fds[0]);
    return {};
  }
  clockid_t child_cpu{};
  const bool can_watch = clock_getcpuclockid(pid, &child_cpu) == 0;
  if (!can_watch) std::fprintf(stderr, "bench: cannot read a child's CPU clock: no CPU limit for it\n");
  bool over_limit = false;
  for (;;) {  // wait for the child's numbers (or its end), checking its CPU every 100 ms
    pollfd ready{fds[0], POLLIN, 0};
    const int polled = poll(&ready, 1, 100);
    if (polled > 0 || (polled < 0 && errno != EINTR)) break;  // numbers, end of file, or an error: read tells
    timespec used{};
    if (can_watch && clock_gettime(child_cpu, &used) == 0 &&
        double(used.tv_sec) + 1e-9 * double(used.tv_nsec) > cpu_limit_seconds) {
      over_limit = true;
      kill(pid, SIGKILL);
      break;
    }
  }
  std::vector<double> values(count + 3, 0.0);
  const auto bytes = static_cast<ssize_t>(values.size() * sizeof(double));
  const bool got = !over_limit && read(fds[0], values.data(), static_cast<std::size_t>(bytes)) == bytes;
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  ChildResult r;
  if (!got || !WIFEXITED(status) || WEXITSTATUS(status) != 0) return r;
  r.ok = true;
  r.peak_mb = values.back();
  values.pop_back();
  r.wall = values.back();
  values.pop_back();
  r.cpu = values.back();
  values.pop_back();
  r.values = values;
  return r;
}

}  // namespace bench
