// Leaving nothing behind when a command is interrupted: temporary files and staging
// directories registered here are removed if SIGINT, SIGTERM or SIGHUP arrives, before the
// process dies of that signal (so its exit status still says which). AtomicFileWriter and
// StagedDirectory register themselves; the handlers are installed only by a program that
// asks (install_interrupt_cleanup, called by the visimp apps): a library must not take
// signals over behind its caller's back. SIGKILL cannot be caught: its debris stays.
#pragma once

#include <cstddef>
#include <string>
#include <system_error>

namespace visimp {

/// Installs the handlers for SIGINT, SIGTERM and SIGHUP (idempotent). A signal that was
/// ignored when the process started (nohup, a shell's background job) stays ignored.
void install_interrupt_cleanup();

/// While alive, a file or a directory of files is removed on an interrupt. At most
/// kMaxCleanupPaths at once; beyond that the path is created unguarded.
class InterruptCleanup {
 public:
  static constexpr std::size_t kMaxCleanupPaths = 64;
  enum class Kind { file, directory };
  /// Creates a unique file (mkstemp) or directory (mkdtemp) from `pattern`, which ends in
  /// "XXXXXX", guarded from the instant it exists: the name is made in the table the
  /// handler reads, so no signal can fall between creating it and registering it. Throws
  /// std::system_error when it cannot be created.
  InterruptCleanup(const std::string& pattern, Kind kind);
  ~InterruptCleanup();
  InterruptCleanup(const InterruptCleanup&) = delete;
  InterruptCleanup& operator=(const InterruptCleanup&) = delete;

  const std::string& path() const { return path_; }
  /// Stop guarding (the path was renamed into place or removed normally).
  void release();

 private:
  int slot_ = -1;
  std::string path_;
};

}  // namespace visimp
