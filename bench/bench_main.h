// What every bench program shares: --help, one clear line and the documented exit codes on
// any error (0 success, 1 bad input or I/O, 2 bad usage, 3 internal), and default meshes that
// fall back to the bundled ones, saying so, when ../shared/meshes is absent.
#pragma once

#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "visimp/core/errors.h"

namespace bench {

/// Runs `body` with --help answered from `usage` and every exception turned into one line
/// on stderr and the matching exit code.
inline int guarded_main(const char* name, const char* usage, int argc, char** argv,
                        const std::function<int(const std::vector<std::string>&)>& body) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  for (const std::string& a : args) {
    if (a == "--help" || a == "-h") {
      std::printf("%s", usage);
      return 0;
    }
  }
  try {
    return body(args);
  } catch (const visimp::UsageError& e) {
    std::fprintf(stderr, "%s: error: %s\n", name, e.what());
    return 2;
  } catch (const visimp::IoError& e) {
    std::fprintf(stderr, "%s: error: %s\n", name, e.what());
    return 1;
  } catch (const visimp::InvalidMeshError& e) {
    std::fprintf(stderr, "%s: error: %s\n", name, e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: internal error: %s\n", name, e.what());
    return 3;
  }
}

/// The shared meshes a benchmark runs on by default; each absent one is replaced by its
/// bundled stand-in (meshes/), or dropped when it has none, with a note on stderr.
inline std::vector<std::string> default_meshes(
    const char* name, const std::vector<std::pair<std::string, std::string>>& shared_and_bundled) {
  std::vector<std::string> paths;
  for (const auto& [shared, bundled] : shared_and_bundled) {
    const std::string path = std::string(VISIMP_SHARED_MESHES_DIR) + "/" + shared;
    if (std::filesystem::exists(path)) {
      paths.push_back(path);
      continue;
    }
    if (bundled.empty()) {
      std::fprintf(stderr, "%s: note: %s is absent (../shared/meshes): left out\n", name, path.c_str());
      continue;
    }
    const std::string stand_in = std::string(VISIMP_MESHES_DIR) + "/" + bundled;
    std::fprintf(stderr, "%s: note: %s is absent (../shared/meshes): using %s instead\n", name, path.c_str(),
                 stand_in.c_str());
    paths.push_back(stand_in);
  }
  // Two shared meshes may fall back to the same bundled one: measure it once.
  std::vector<std::string> unique;
  for (const std::string& p : paths)
    if (std::find(unique.begin(), unique.end(), p) == unique.end()) unique.push_back(p);
  if (unique.empty()) throw visimp::UsageError("no mesh to measure: give mesh paths as arguments");
  return unique;
}

}  // namespace bench
