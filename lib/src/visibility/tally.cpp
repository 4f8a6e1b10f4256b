// Tally arithmetic and the slice file format (see tally.h).
#include "visimp/visibility/tally.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>

#include "visimp/core/errors.h"
#include "visimp/io/atomic_file.h"
#include "visimp/io/byte_stream.h"
#include "visimp/io/mesh_io.h"

namespace visimp {
namespace {

constexpr char kMagic[8] = {'V', 'I', 'S', 'I', 'M', 'P', 'T', '2'};

}  // namespace

bool TallyKey::operator==(const TallyKey& o) const {
  return mesh_hash == o.mesh_hash && camera_hash == o.camera_hash && camera_count == o.camera_count &&
         faces == o.faces && one_sided_faces == o.one_sided_faces && resolution == o.resolution && flags == o.flags &&
         worst_view_cosine == o.worst_view_cosine && depth_tolerance_pixels == o.depth_tolerance_pixels;
}

void VisibilityTally::merge(const VisibilityTally& other) {
  if (key != other.key) {
    throw UsageError("tallies come from different meshes, camera sets or options and cannot be merged");
  }
  std::vector<std::pair<std::uint64_t, std::uint64_t>> ranges = camera_ranges;
  ranges.insert(ranges.end(), other.camera_ranges.begin(), other.camera_ranges.end());
  std::sort(ranges.begin(), ranges.end());
  for (std::size_t i = 1; i < ranges.size(); ++i) {
    if (ranges[i].first < ranges[i - 1].second) {
      throw UsageError("camera ranges " + std::to_string(ranges[i - 1].first) + ".." +
                       std::to_string(ranges[i - 1].second) + " and " + std::to_string(ranges[i].first) + ".." +
                       std::to_string(ranges[i].second) + " overlap: a camera would be counted twice");
    }
  }
  // Keep the list short: join ranges that touch.
  camera_ranges.clear();
  for (const auto& r : ranges) {
    if (!camera_ranges.empty() && camera_ranges.back().second == r.first) {
      camera_ranges.back().second = r.second;
    } else if (r.first < r.second) {
      camera_ranges.push_back(r);
    }
  }
  for (std::size_t t = 0; t < seen.size(); ++t) {
    seen[t] += other.seen[t];
    total[t] += other.total[t];
  }
  for (std::size_t t = 0; t < seen_back.size(); ++t) {
    seen_back[t] += other.seen_back[t];
    total_back[t] += other.total_back[t];
  }
}

void VisibilityTally::reset_sums() {
  seen.assign(key.faces, 0);
  total.assign(key.faces, 0);
  seen_back.assign(key.faces - key.one_sided_faces, 0);
  total_back.assign(key.faces - key.one_sided_faces, 0);
}

bool VisibilityTally::complete() const {
  return camera_ranges.size() == 1 && camera_ranges[0].first == 0 && camera_ranges[0].second == key.camera_count;
}

std::string VisibilityTally::describe_ranges() const {
  std::string s;
  for (const auto& r : camera_ranges) {
    if (!s.empty()) s += ", ";
    s += std::to_string(r.first) + ".." + std::to_string(r.second);
  }
  return s.empty() ? "none" : s;
}

std::string VisibilityTally::describe_missing() const {
  std::string s;
  std::uint64_t next = 0;
  auto add = [&](std::uint64_t a, std::uint64_t b) {
    if (a >= b) return;
    if (!s.empty()) s += ", ";
    s += std::to_string(a) + ".." + std::to_string(b);
  };
  for (const auto& r : camera_ranges) {
    add(next, r.first);
    next = r.second;
  }
  add(next, key.camera_count);
  return s.empty() ? "none" : s;
}

void VisibilityTally::write(const std::string& path) const {
  const std::string data = bytes();
  AtomicFileWriter file(path);
  file.stream().write(data.data(), static_cast<std::streamsize>(data.size()));
  file.commit();
}

std::string VisibilityTally::bytes() const {
  ByteWriter w;
  w.bytes.assign(kMagic, kMagic + 8);
  w.u64(key.mesh_hash);
  w.u64(key.camera_hash);
  w.u64(key.camera_count);
  w.u64(key.faces);
  w.u64(key.one_sided_faces);
  w.u32(key.resolution);
  w.u32(key.flags);
  w.f64(key.worst_view_cosine);
  w.f64(key.depth_tolerance_pixels);
  w.u64(camera_ranges.size());
  for (const auto& r : camera_ranges) {
    w.u64(r.first);
    w.u64(r.second);
  }
  for (std::uint32_t v : seen) w.u32(v);
  for (std::uint32_t v : total) w.u32(v);
  for (std::uint32_t v : seen_back) w.u32(v);
  for (std::uint32_t v : total_back) w.u32(v);
  return std::string(w.bytes.begin(), w.bytes.end());
}

VisibilityTally VisibilityTally::read(const std::string& path) { return parse(read_file_bytes(path), path); }

VisibilityTally VisibilityTally::parse(const std::string& bytes, const std::string& path) {
  ByteReader r(path, bytes, "tally");
  r.expect_magic(kMagic, "visimp visibility tally");
  VisibilityTally t;
  t.key.mesh_hash = r.u64();
  t.key.camera_hash = r.u64();
  t.key.camera_count = r.u64();
  t.key.faces = r.u64();
  t.key.one_sided_faces = r.u64();
  t.key.resolution = r.u32();
  t.key.flags = r.u32();
  t.key.worst_view_cosine = r.f64();
  t.key.depth_tolerance_pixels = r.f64();
  const std::uint64_t ranges = r.u64();
  if (ranges > r.remaining() / 16)
    throw IoError(path, "camera range count " + std::to_string(ranges) + " exceeds the file");
  for (std::uint64_t i = 0; i < ranges; ++i) {
    const std::uint64_t first = r.u64(), last = r.u64();
    if (first > last || last > t.key.camera_count) throw IoError(path, "camera range out of order or beyond the set");
    t.camera_ranges.emplace_back(first, last);
  }
  if (t.key.camera_count > kMaxCameras) throw IoError(path, "more than 65536 cameras");
  if (t.key.one_sided_faces > t.key.faces) throw IoError(path, "more one-sided faces than faces");
  const std::uint64_t two_sided = t.key.faces - t.key.one_sided_faces;
  // Compare in faces, not bytes: a huge face count must not overflow the expected size.
  if (r.remaining() % 8 != 0 || r.remaining() / 8 < t.key.faces || (r.remaining() / 8 - t.key.faces) != two_sided) {
    throw IoError(path, "expected " + std::to_string(t.key.faces) + " faces of tallies (" + std::to_string(two_sided) +
                            " two-sided), found " + std::to_string(r.remaining()) + " bytes");
  }
  t.reset_sums();
  for (auto& v : t.seen) v = r.u32();
  for (auto& v : t.total) v = r.u32();
  for (auto& v : t.seen_back) v = r.u32();
  for (auto& v : t.total_back) v = r.u32();
  for (std::size_t f = 0; f < t.seen.size(); ++f) {
    if (t.seen[f] > t.total[f]) throw IoError(path, "face " + std::to_string(f) + " is seen more than it is faced");
  }
  for (std::size_t f = 0; f < t.seen_back.size(); ++f) {
    if (t.seen_back[f] > t.total_back[f]) {
      throw IoError(path,
                    "face " + std::to_string(t.key.one_sided_faces + f) + " is seen from behind more than it is faced");
    }
  }
  return t;
}

}  // namespace visimp
