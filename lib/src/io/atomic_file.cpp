#include "visimp/io/atomic_file.h"

#include <fcntl.h>
#include <stdio.h>  // renameat2
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <vector>

#include "visimp/core/errors.h"

namespace visimp {

namespace {
mode_t current_umask() {
  const mode_t mask = ::umask(0);
  ::umask(mask);
  return mask;
}
}  // namespace

AtomicFileWriter::AtomicFileWriter(std::string target) : target_(std::move(target)) {
  namespace fs = std::filesystem;
  const fs::path target_path(target_);
  fs::path dir = target_path.parent_path();
  if (dir.empty()) dir = ".";
  const std::string pattern = (dir / ("." + target_path.filename().string() + ".visimp-XXXXXX")).string();
  try {
    cleanup_ = std::make_unique<InterruptCleanup>(pattern, InterruptCleanup::Kind::file);
  } catch (const std::system_error& e) {
    throw IoError(target_, std::string("cannot create a temporary file: ") + std::strerror(e.code().value()));
  }
  temp_ = cleanup_->path();
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
  ::chmod(temp_.c_str(), 0666 & ~current_umask());
  if (std::rename(temp_.c_str(), target_.c_str()) != 0)
    throw IoError(target_, std::string("cannot rename temporary file into place: ") + std::strerror(errno));
  committed_ = true;
  cleanup_->release();
}

StagedDirectory::StagedDirectory(std::string target) : target_(std::move(target)) {
  namespace fs = std::filesystem;
  while (target_.size() > 1 && target_.back() == '/') target_.pop_back();
  const fs::path target_path(target_);
  fs::path parent = target_path.parent_path();
  if (parent.empty()) parent = ".";
  std::error_code ec;
  fs::create_directories(parent, ec);
  if (ec) throw IoError(target_, "cannot create the parent directory: " + ec.message());
  if (fs::exists(target_path, ec) && !fs::is_directory(target_path, ec)) {
    throw IoError(target_, "exists and is not a directory");
  }
  const std::string pattern = (parent / ("." + target_path.filename().string() + ".visimp-XXXXXX")).string();
  try {
    cleanup_ = std::make_unique<InterruptCleanup>(pattern, InterruptCleanup::Kind::directory);
  } catch (const std::system_error& e) {
    throw IoError(target_, std::string("cannot create a staging directory: ") + std::strerror(e.code().value()));
  }
  staging_ = cleanup_->path();
  ::chmod(staging_.c_str(), 0777 & ~current_umask());  // mkdtemp makes 0700
}

StagedDirectory::~StagedDirectory() {
  std::error_code ignored;
  if (!committed_) std::filesystem::remove_all(staging_, ignored);
}

void StagedDirectory::commit() {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(target_, ec)) {
    if (std::rename(staging_.c_str(), target_.c_str()) != 0)
      throw IoError(target_, std::string("cannot move the new directory into place: ") + std::strerror(errno));
  } else if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, target_.c_str(), RENAME_EXCHANGE) != 0) {
    // No exchange on this file system: move the old one aside, then the new one in.
    const std::string aside = staging_ + "-old";
    if (std::rename(target_.c_str(), aside.c_str()) != 0)
      throw IoError(target_, std::string("cannot move the old directory aside: ") + std::strerror(errno));
    if (std::rename(staging_.c_str(), target_.c_str()) != 0) {
      const int err = errno;
      std::rename(aside.c_str(), target_.c_str());
      throw IoError(target_, std::string("cannot move the new directory into place: ") + std::strerror(err));
    }
    fs::remove_all(aside, ec);
  } else {
    fs::remove_all(staging_, ec);  // now the old directory
  }
  committed_ = true;
  cleanup_->release();
}

}  // namespace visimp
