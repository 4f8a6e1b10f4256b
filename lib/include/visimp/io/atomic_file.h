// Writes a file so that readers only ever see the old file or the complete new one: data goes
// to a temporary file in the same directory, which is flushed, fsynced and renamed over the
// target by commit(). Destroying the writer without commit() removes the temporary file.
#pragma once

#include <fstream>
#include <memory>
#include <string>

#include "visimp/io/interrupt_cleanup.h"

namespace visimp {

class AtomicFileWriter {
 public:
  /// Creates the temporary file; throws IoError naming `target` on failure.
  explicit AtomicFileWriter(std::string target);
  ~AtomicFileWriter();
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;

  std::ostream& stream() { return out_; }
  /// Flushes, fsyncs and renames into place; throws IoError if any step failed.
  void commit();
  const std::string& temp_path() const { return temp_; }

 private:
  std::string target_, temp_;
  std::ofstream out_;
  bool committed_ = false;
  std::unique_ptr<InterruptCleanup> cleanup_;  // removes temp_ on SIGINT/SIGTERM/SIGHUP
};

/// A directory of outputs that appears all at once or not at all: files go into a staging
/// directory beside `target` (".NAME.visimp-XXXXXX"), and commit() swaps it in, so readers
/// see either the old directory, whole, or the new one. Without commit() (an error, an
/// exception, an interrupt) the staging directory is removed and `target` is untouched.
/// The directory must be flat (files only): that is what the interrupt handler can remove.
class StagedDirectory {
 public:
  /// Creates the staging directory; throws IoError naming `target` on failure.
  explicit StagedDirectory(std::string target);
  ~StagedDirectory();
  StagedDirectory(const StagedDirectory&) = delete;
  StagedDirectory& operator=(const StagedDirectory&) = delete;

  /// Where to write the files now.
  const std::string& path() const { return staging_; }
  /// Replaces `target` (if it exists, atomically where the file system can exchange two
  /// names) by the staged directory; the old one is removed. Throws IoError.
  void commit();

 private:
  std::string target_, staging_;
  bool committed_ = false;
  std::unique_ptr<InterruptCleanup> cleanup_;
};

}  // namespace visimp
