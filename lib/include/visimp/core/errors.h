// visimp's one error policy: bad input and I/O failures throw these typed exceptions (all
// derived from the standard ones); broken internal invariants are asserts. Messages speak
// the library's terms (struct fields, not command-line flags); the apps catch in main, turn
// an OptionError back into the flag the user typed, print one line and choose the exit code.
#pragma once

#include <stdexcept>
#include <string>

namespace visimp {

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

/// A field of an options struct is out of range: what() is "SimplifyOptions::target_ratio must
/// be in [0, 1]". `field` is the member's address (nullptr when several fields are at fault),
/// so a front end that bound a flag to it can say "--ratio must be in [0, 1]" instead.
class OptionError : public UsageError {
 public:
  OptionError(const void* field, const std::string& name, const std::string& problem)
      : UsageError(name + " " + problem), field_(field), problem_(problem) {}
  const void* field() const { return field_; }
  const std::string& problem() const { return problem_; }

 private:
  const void* field_;
  std::string problem_;
};

/// A rendering backend cannot run here (no OpenGL 4.5 context from OSMesa, for example).
class BackendError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace visimp
