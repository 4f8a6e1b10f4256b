// Writes a file so that readers only ever see the old file or the complete new one: data goes
// to a temporary file in the same directory, which is flushed, fsynced and renamed over the
// target by commit(). Destroying the writer without commit() removes the temporary file.
#pragma once

#include <fstream>
#include <string>

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
};

}  // namespace visimp
