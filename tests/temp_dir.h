// A scratch directory for one test, removed with everything in it when the test's scope ends,
// whether its assertions held or not (an ASSERT_* returns early; the destructor still runs).
#pragma once

#include <stdlib.h>  // mkdtemp

#include <cerrno>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

namespace visimp::test {

class TempDir {
 public:
  /// Creates a fresh, empty <system temp>/visimp_test_<name>_XXXXXX (mkdtemp: unique even for
  /// tests run in parallel or twice in one process). Characters of `name` other than
  /// [A-Za-z0-9_-] become '_', so a parameterised test's name may be passed as it is.
  /// Throws std::system_error when the directory cannot be created.
  explicit TempDir(const std::string& name) {
    std::string safe = name;
    for (char& c : safe) {
      const bool plain =
          (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
      if (!plain) c = '_';
    }
    const std::string pattern = (std::filesystem::temp_directory_path() / ("visimp_test_" + safe + "_XXXXXX")).string();
    std::vector<char> buf(pattern.begin(), pattern.end());
    buf.push_back('\0');
    if (::mkdtemp(buf.data()) == nullptr) throw std::system_error(errno, std::generic_category(), "mkdtemp " + pattern);
    path_ = buf.data();
  }
  /// Removes the directory and its contents; errors are ignored (a destructor must not throw,
  /// and a leftover is then visible in the temp folder rather than failing an unrelated test).
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  /// The directory, without a trailing '/'.
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace visimp::test
