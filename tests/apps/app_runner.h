// Runs the `visimp` binary (VISIMP_APP) the way a pipeline would, for end-to-end tests.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace visimp::test {

inline std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

struct AppRun {
  int code;  ///< exit code, -1 if the process did not exit normally
  std::string out, err;
};

/// `visimp ARGS` with stdout and stderr captured in files under `dir`, stdin from `stdin_file`.
inline AppRun run(const std::string& args, const std::string& dir, const std::string& stdin_file = "") {
  const std::string out = dir + "/stdout.txt", err = dir + "/stderr.txt";
  std::string cmd = std::string(VISIMP_APP) + " " + args + " >" + out + " 2>" + err;
  if (!stdin_file.empty()) cmd += " <" + stdin_file;
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
}

}  // namespace visimp::test
