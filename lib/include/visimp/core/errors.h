// visimp's one error policy: bad input and I/O failures throw these typed exceptions (all
// derived from the standard ones); broken internal invariants are asserts. Apps catch in
// main, print one line and exit with the code below.
#pragma once

#include <stdexcept>
#include <string>

namespace visimp {

/// Process exit codes used by every visimp app (documented in README and --help).
enum ExitCode : int {
  kExitSuccess = 0,
  kExitBadInput = 1,   ///< a file could not be read, parsed or written, or a mesh is invalid
  kExitBadUsage = 2,   ///< unknown flag, missing or malformed argument
  kExitInternal = 3,   ///< anything else: a bug in visimp
};

/// A file could not be opened, read, parsed or written. what() names the file and, where
/// known, the line or byte offset: "bunny.ply: line 12: face 7 has index 9999 >= 3674 vertices".
class IoError : public std::runtime_error {
 public:
  IoError(const std::string& file, const std::string& problem)
      : std::runtime_error(file + ": " + problem), file_(file), problem_(problem) {}
  const std::string& file() const { return file_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string file_, problem_;
};

/// A mesh's content breaks a contract (index out of range, non-finite coordinate, quality
/// array of the wrong size).
class InvalidMeshError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// An option or argument is out of range or malformed.
class UsageError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

}  // namespace visimp
