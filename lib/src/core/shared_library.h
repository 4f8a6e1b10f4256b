// Private to the library: a backend's shared library opened at its first use instead of
// linked. OSMesa (with Mesa's LLVM behind it) cost every process that linked it ~65 ms of
// relocations at start-up, `visimp --help` and `visimp info` included; opened here, only a
// process that renders with GL pays. The library stays loaded for the process's life (its
// worker threads and caches outlive any one renderer), so it is never closed. (Embree was
// opened this way too and went back to being linked: lib/CMakeLists.txt says why.)
#pragma once

#include <dlfcn.h>

#include <string>

#include "visimp/core/errors.h"

namespace visimp::detail {

class SharedLibrary {
 public:
  /// Opens `soname` (as the build found it); BackendError naming it, the Debian package that
  /// holds it and the loader's reason if it cannot.
  SharedLibrary(const char* soname, const char* debian_package) : soname_(soname) {
    handle_ = dlopen(soname, RTLD_NOW | RTLD_LOCAL);
    if (handle_ == nullptr) {
      const char* why = dlerror();
      throw BackendError(std::string("cannot load ") + soname + " (Debian: " + debian_package +
                         "): " + (why != nullptr ? why : "unknown error"));
    }
  }

  /// Sets `function` to the library's `symbol`; BackendError if it has none.
  template <class Function>
  void resolve(const char* symbol, Function& function) const {
    function = reinterpret_cast<Function>(dlsym(handle_, symbol));
    if (function == nullptr) {
      const char* why = dlerror();
      throw BackendError(std::string(soname_) + " has no " + symbol + (why != nullptr ? std::string(": ") + why : ""));
    }
  }

 private:
  const char* soname_;
  void* handle_ = nullptr;
};

}  // namespace visimp::detail
