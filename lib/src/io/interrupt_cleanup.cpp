#include "visimp/io/interrupt_cleanup.h"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <mutex>

namespace visimp {
namespace {

// A fixed table, so the handler needs no allocation and no lock: a slot is claimed (free →
// claimed), filled, then armed; the handler only reads armed slots.
enum SlotState : int { kFree = 0, kClaimed = 1, kArmed = 2 };
constexpr std::size_t kPathBytes = 4096;

struct Slot {
  std::atomic<int> state{kFree};
  bool directory = false;
  char path[kPathBytes] = {};
};
Slot g_slots[InterruptCleanup::kMaxCleanupPaths];

// Removes the files of a flat directory and the directory, with system calls only
// (async-signal-safe: no opendir, which allocates).
void remove_flat_directory(const char* path) {
  const int fd = ::open(path, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd >= 0) {
    alignas(8) char buffer[4096];
    for (;;) {
      const long n = ::syscall(SYS_getdents64, fd, buffer, sizeof buffer);
      if (n <= 0) break;
      for (long offset = 0; offset < n;) {
        const auto* entry = reinterpret_cast<const dirent64*>(buffer + offset);
        const char* name = entry->d_name;
        const bool dot = name[0] == '.' && (name[1] == '\0' || (name[1] == '.' && name[2] == '\0'));
        if (!dot) ::unlinkat(fd, name, 0);
        offset += entry->d_reclen;
      }
    }
    ::close(fd);
  }
  ::rmdir(path);
}

void on_interrupt(int sig) {
  for (Slot& slot : g_slots) {
    if (slot.state.load(std::memory_order_acquire) != kArmed) continue;
    if (slot.directory) {
      remove_flat_directory(slot.path);
    } else {
      ::unlink(slot.path);
    }
  }
  // Die of the same signal, so a shell or a pipeline sees what happened.
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

}  // namespace

void install_interrupt_cleanup() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
      struct sigaction old {};
      if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
      struct sigaction action {};
      action.sa_handler = on_interrupt;
      sigemptyset(&action.sa_mask);
      ::sigaction(sig, &action, nullptr);
    }
  });
}

namespace {

// mkstemp or mkdtemp in place; true on success.
bool create_in(char* name, InterruptCleanup::Kind kind) {
  if (kind == InterruptCleanup::Kind::directory) return ::mkdtemp(name) != nullptr;
  const int fd = ::mkstemp(name);
  if (fd < 0) return false;
  ::close(fd);
  return true;
}

}  // namespace

InterruptCleanup::InterruptCleanup(const std::string& pattern, Kind kind) {
  if (pattern.size() < kPathBytes) {
    for (std::size_t i = 0; i < kMaxCleanupPaths; ++i) {
      int expected = kFree;
      if (!g_slots[i].state.compare_exchange_strong(expected, kClaimed, std::memory_order_acq_rel)) continue;
      Slot& slot = g_slots[i];
      std::memcpy(slot.path, pattern.c_str(), pattern.size() + 1);
      slot.directory = kind == Kind::directory;
      // Armed before the name exists: the handler may meet the pattern, or a name mkstemp is
      // trying, and remove nothing; once the file exists its name is what the slot holds.
      slot.state.store(kArmed, std::memory_order_release);
      if (!create_in(slot.path, kind)) {
        const int err = errno;
        slot.state.store(kFree, std::memory_order_release);
        throw std::system_error(err, std::generic_category(), "cannot create " + pattern);
      }
      slot_ = static_cast<int>(i);
      path_ = slot.path;
      return;
    }
  }
  std::string name = pattern;  // no free slot: created unguarded
  if (!create_in(name.data(), kind))
    throw std::system_error(errno, std::generic_category(), "cannot create " + pattern);
  path_ = name;
}

InterruptCleanup::~InterruptCleanup() { release(); }

void InterruptCleanup::release() {
  if (slot_ < 0) return;
  g_slots[slot_].state.store(kFree, std::memory_order_release);
  slot_ = -1;
}

}  // namespace visimp
