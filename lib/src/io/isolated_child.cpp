#include "isolated_child.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <new>

// Present only in sanitizer builds (weak: null otherwise). libFuzzer registers a death callback
// that saves the input as a "crash" when ASan ends a process; a child's end is not one of ours.
extern "C" void __sanitizer_set_death_callback(void (*callback)(void)) __attribute__((weak));

namespace visimp::detail {
namespace {

constexpr char kAnswer = 'A', kError = 'E';

// The data segment the parent already has (VmData: heap, private writable mappings; under
// ASan, its shadow memory too), which the child's limit comes on top of.
std::size_t data_bytes() {
  std::ifstream status("/proc/self/status");
  std::string key;
  while (status >> key) {
    if (key == "VmData:") {
      std::size_t kib = 0;
      status >> kib;
      return kib << 10;
    }
    status.ignore(1 << 12, '\n');
  }
  return 0;
}

void write_all(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) _exit(3);  // the parent is gone or the pipe broke: nothing to tell anyone
    data += n;
    size -= std::size_t(n);
  }
}

void send(int fd, char kind, const std::string& body) {
  const std::uint64_t size = body.size();
  write_all(fd, &kind, 1);
  write_all(fd, reinterpret_cast<const char*>(&size), sizeof size);
  write_all(fd, body.data(), body.size());
}

[[noreturn]] void be_the_child(int fd, const std::function<std::string()>& work, const ChildLimits& limits) {
  // Die by the signal itself: a sanitizer's or fuzzer's handler would report the library's
  // fault as ours; the parent names the signal.
  for (const int s : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) ::signal(s, SIG_DFL);
  if (__sanitizer_set_death_callback != nullptr) __sanitizer_set_death_callback(nullptr);
  // RLIMIT_DATA (Linux >= 4.7 counts every private writable mapping, so malloc's mmap too),
  // not RLIMIT_AS: it works under ASan, whose reserved shadow is counted at its real size.
  const auto data_limit = rlim_t(data_bytes() + limits.extra_memory);
  const rlimit memory{data_limit, data_limit};
  ::setrlimit(RLIMIT_DATA, &memory);
  const rlimit cpu{rlim_t(limits.cpu_seconds), rlim_t(limits.cpu_seconds + 5)};
  ::setrlimit(RLIMIT_CPU, &cpu);
  try {
    send(fd, kAnswer, work());
  } catch (const std::bad_alloc&) {
    send(fd, kError, "ran out of memory (limit " + std::to_string(limits.extra_memory >> 20) + " MiB)");
  } catch (const std::exception& e) {
    send(fd, kError, e.what());
  } catch (...) {
    send(fd, kError, "failed with an unknown exception");
  }
  _exit(0);  // no atexit handlers, no stdio flush: the parent owns those
}

std::string read_to_end(int fd) {
  std::string data;
  char buffer[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    data.append(buffer, std::size_t(n));
  }
  return data;
}

std::string describe_death(int status, const ChildLimits& limits) {
  if (WIFSIGNALED(status)) {
    const int s = WTERMSIG(status);
    if (s == SIGXCPU) return "took more than " + std::to_string(limits.cpu_seconds) + " CPU seconds";
    if (s == SIGKILL) return "was killed (SIGKILL; out of memory?)";
    const char* name = ::strsignal(s);
    return "crashed (signal " + std::to_string(s) + ": " + (name ? name : "unknown") + ")";
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) != 0) return "exited with code " + std::to_string(WEXITSTATUS(status));
  return "ended without an answer";
}

}  // namespace

std::string run_in_child(const std::function<std::string()>& work, const ChildLimits& limits) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) throw ChildFailure(std::string("cannot create a pipe: ") + std::strerror(errno));
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int e = errno;
    ::close(fds[0]);
    ::close(fds[1]);
    throw ChildFailure(std::string("cannot fork: ") + std::strerror(e));
  }
  if (pid == 0) {
    ::close(fds[0]);
    be_the_child(fds[1], work, limits);
  }
  ::close(fds[1]);
  const std::string data = read_to_end(fds[0]);
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  constexpr std::size_t header = 1 + sizeof(std::uint64_t);
  std::uint64_t size = 0;
  if (data.size() >= header) std::memcpy(&size, data.data() + 1, sizeof size);
  const bool complete = data.size() >= header && data.size() - header == size;
  if (!complete) throw ChildFailure(describe_death(status, limits));
  std::string body = data.substr(header);
  if (data[0] == kError) throw ChildFailure(body);
  return body;
}

}  // namespace visimp::detail
