// Explicit little-endian encoding for visimp's binary files (tallies, bitfields): they may
// travel between machines, so nothing depends on the host's byte order or padding.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <utility>

#include "visimp/core/errors.h"

namespace visimp {

class ByteWriter {
 public:
  void u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
  }
  void u64(std::uint64_t v) {
    for (int i = 0; i < 8; ++i) bytes.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
  }
  void f64(double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, 8);
    u64(bits);
  }
  /// LEB128: 7 bits a byte, low first.
  void varint(std::uint64_t v) {
    while (v >= 0x80) {
      bytes.push_back(static_cast<char>((v & 0x7f) | 0x80));
      v >>= 7;
    }
    bytes.push_back(static_cast<char>(v));
  }
  std::string bytes;
};

/// Reads what ByteWriter wrote; throws IoError naming the file and the byte for truncation.
class ByteReader {
 public:
  /// `what` names the kind of file in messages ("tally", "bitfield file").
  /// Reads `bytes`, kept by reference (they must outlive the reader; a temporary is refused);
  /// `path` is copied.
  ByteReader(std::string path, const std::string& bytes, std::string what)
      : path_(std::move(path)), bytes_(bytes), what_(std::move(what)) {}
  ByteReader(std::string path, const std::string&& bytes, std::string what) = delete;
  std::uint64_t u64() { return read(8); }
  std::uint32_t u32() { return static_cast<std::uint32_t>(read(4)); }
  double f64() {
    const std::uint64_t bits = u64();
    double v;
    std::memcpy(&v, &bits, 8);
    return v;
  }
  std::uint64_t varint() {
    std::uint64_t v = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      const std::uint64_t b = read(1);
      v |= (b & 0x7f) << shift;
      if ((b & 0x80) == 0) return v;
    }
    throw IoError(path_, "malformed number in the " + what_ + " at byte " + std::to_string(pos_));
  }
  std::string text(std::size_t n) {
    if (remaining() < n) truncated();
    std::string s = bytes_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  std::size_t remaining() const { return bytes_.size() - pos_; }
  std::size_t position() const { return pos_; }
  /// Checks the first 8 bytes; `kind` says what the file should have been.
  void expect_magic(const char (&magic)[8], const std::string& kind) {
    if (bytes_.size() < 8 || std::memcmp(bytes_.data(), magic, 8) != 0) {
      throw IoError(path_, "not a " + kind + " (bad magic)");
    }
    pos_ = 8;
  }

 private:
  [[noreturn]] void truncated() const {
    throw IoError(path_, "truncated " + what_ + " at byte " + std::to_string(pos_));
  }
  std::uint64_t read(int n) {
    if (remaining() < static_cast<std::size_t>(n)) truncated();
    std::uint64_t v = 0;
    for (int i = 0; i < n; ++i) v |= std::uint64_t{static_cast<unsigned char>(bytes_[pos_ + i])} << (8 * i);
    pos_ += static_cast<std::size_t>(n);
    return v;
  }
  std::string path_;
  const std::string& bytes_;
  std::string what_;
  std::size_t pos_ = 0;
};

}  // namespace visimp
