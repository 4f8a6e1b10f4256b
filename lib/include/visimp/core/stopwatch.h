// Wall-clock seconds for the per-stage timings every report carries.
#pragma once

#include <chrono>

namespace visimp {

inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace visimp
