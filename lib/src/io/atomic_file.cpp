#include "visimp/io/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <vector>

#include "visimp/core/errors.h"

namespace visimp {

AtomicFileWriter::AtomicFileWriter(std::string target) : target_(std::move(target)) {
  namespace fs = std::filesystem;
  const fs::path target_path(target_);
  fs::path dir = target_path.parent_path();
  if (dir.empty()) dir = ".";
  std::string pattern = (dir / ("." + target_path.filename().string() + ".visimp-XXXXXX")).string();
  std::vector<char> buf(pattern.begin(), pattern.end());
  buf.push_back('\0');
  const int fd = ::mkstemp(buf.data());
  if (fd < 0) throw IoError(target_, std::string("cannot create a temporary file: ") + std::strerror(errno));
  ::close(fd);
  temp_ = buf.data();
  out_.open(temp_, std::ios::binary | std::ios::trunc);
  if (!out_) {
    ::unlink(temp_.c_str());
    throw IoError(target_, "cannot open temporary file " + temp_);
  }
}

AtomicFileWriter::~AtomicFileWriter() {
  if (!committed_) {
    out_.close();
    ::unlink(temp_.c_str());
  }
}

void AtomicFileWriter::commit() {
  out_.flush();
  const bool ok = static_cast<bool>(out_);
  out_.close();
  if (!ok || out_.fail()) throw IoError(target_, "write failed (disk full?)");
  const int fd = ::open(temp_.c_str(), O_RDONLY);
  if (fd < 0 || ::fsync(fd) != 0) {
    const int err = errno;
    if (fd >= 0) ::close(fd);
    throw IoError(target_, std::string("cannot sync temporary file: ") + std::strerror(err));
  }
  ::close(fd);
  // mkstemp makes 0600 files; give the output the permissions a plain create would.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ::chmod(temp_.c_str(), 0666 & ~mask);
  if (std::rename(temp_.c_str(), target_.c_str()) != 0)
    throw IoError(target_, std::string("cannot rename temporary file into place: ") + std::strerror(errno));
  committed_ = true;
}

}  // namespace visimp
