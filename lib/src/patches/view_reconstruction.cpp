// View reconstruction (see view_reconstruction.h).
#include "visimp/patches/view_reconstruction.h"

#include <algorithm>

namespace visimp {

ViewReconstructor::ViewReconstructor(const BitfieldSet& set, bool precompute_cells)
    : set_(set), selector_(set.cameras) {
  const std::size_t units = set.bits.units;
  unit_face_offsets_.assign(units + 1, 0);
  for (std::size_t f = 0; f < set.faces; ++f) ++unit_face_offsets_[set.unit_of(f) + 1];
  for (std::size_t u = 0; u < units; ++u) unit_face_offsets_[u + 1] += unit_face_offsets_[u];
  unit_faces_.resize(set.faces);
  std::vector<std::uint32_t> next(unit_face_offsets_.begin(), unit_face_offsets_.end() - 1);
  for (std::size_t f = 0; f < set.faces; ++f) unit_faces_[next[set.unit_of(f)]++] = static_cast<std::uint32_t>(f);

  if (precompute_cells) {
    const std::size_t words = set.bits.words_per_row;
    cell_rows_.assign(selector_.cells() * words, 0);
    for (std::uint32_t c = 0; c < selector_.cells(); ++c) {
      const SampleChoice choice = selector_.samples_of_cell(c);
      std::uint64_t* out = cell_rows_.data() + c * words;
      for (std::size_t s = 0; s < choice.count; ++s) {
        const std::uint64_t* row = set.bits.row(choice.samples[s]);
        for (std::size_t w = 0; w < words; ++w) out[w] |= row[w];
      }
    }
  }
}

Vec3 ViewReconstructor::direction_to(const Vec3& viewpoint) const {
  const Vec3 d = viewpoint - set_.center;
  return norm(d) > 0 ? d : Vec3{0, 0, 1};
}

bool ViewReconstructor::inside_sphere(const Vec3& viewpoint) const {
  // A little slack: a viewpoint placed on the sphere must not count as inside by rounding.
  return norm(viewpoint - set_.center) < set_.radius * (1 - 1e-9);
}

void ViewReconstructor::join(const Vec3& direction, std::uint64_t* out) const {
  const std::size_t words = set_.bits.words_per_row;
  const std::uint32_t cell = selector_.cell(direction);
  if (!cell_rows_.empty()) {
    std::copy_n(cell_rows_.data() + cell * words, words, out);
    return;
  }
  const SampleChoice choice = selector_.samples_of_cell(cell);
  std::copy_n(set_.bits.row(choice.samples[0]), words, out);
  for (std::size_t s = 1; s < choice.count; ++s) {
    const std::uint64_t* row = set_.bits.row(choice.samples[s]);
    for (std::size_t w = 0; w < words; ++w) out[w] |= row[w];
  }
}

std::vector<std::uint32_t> ViewReconstructor::units(const Vec3& direction) const {
  std::vector<std::uint64_t> joined(words_per_row());
  join(direction, joined.data());
  std::vector<std::uint32_t> out;
  for_each_set_bit(joined.data(), joined.size(), [&](std::size_t u) { out.push_back(static_cast<std::uint32_t>(u)); });
  return out;
}

std::vector<std::uint32_t> ViewReconstructor::faces(const Vec3& direction) const {
  std::vector<std::uint32_t> out;
  for (std::uint32_t u : units(direction)) {
    out.insert(out.end(), unit_faces_.begin() + unit_face_offsets_[u], unit_faces_.begin() + unit_face_offsets_[u + 1]);
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::size_t ViewReconstructor::face_count(const std::uint64_t* joined) const {
  std::size_t n = 0;
  for_each_set_bit(joined, words_per_row(),
                   [&](std::size_t u) { n += unit_face_offsets_[u + 1] - unit_face_offsets_[u]; });
  return n;
}

}  // namespace visimp
