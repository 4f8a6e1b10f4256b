// Patch-ID and ID-bitfields (Meruvia Pastor & Strothotte; Meruvia Pastor §3.2.2): for every
// camera of a spherical sampling, one bit per unit — a patch, or a face when every face is
// its own patch — set when the unit owns a pixel of that camera's ID frame.
//
// BitfieldRecorder is a FrameConsumer, so the frames that feed the visibility tally can
// fill the bitfields in the same pass (VisibilityJob::render's `also`; FrameFanOut).
// Options from the ID-bitfield paper:
//   depth test (Zhang & Turk §4, on by default): thin faces, which own pixel centres in
//     some views and not in the next, are set when a vertex is at the visible depth;
//   neighbour fill (§3.1.1): a face that owns no pixel but shares an edge with one that
//     does, and faces the camera, is set too (one pass per frame, from the pixel-seen faces);
//   transparent faces (§3.4): left out of the renders (they hide nothing) and set in every
//     row (whether they are in front of or behind what is drawn is not known).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "visimp/cameras/camera_set.h"
#include "visimp/core/mesh.h"
#include "visimp/patches/patch_partition.h"
#include "visimp/render/renderer.h"

namespace visimp {

/// One row of `units` bits per camera, packed little-endian in 64-bit words (unit u is bit
/// u % 64 of word u / 64; the unused high bits of the last word are zero).
struct Bitfields {
  std::size_t units = 0, cameras = 0, words_per_row = 0;
  std::vector<std::uint64_t> words;

  Bitfields() = default;
  Bitfields(std::size_t units, std::size_t cameras);

  std::uint64_t* row(std::size_t camera) { return words.data() + camera * words_per_row; }
  const std::uint64_t* row(std::size_t camera) const { return words.data() + camera * words_per_row; }
  bool test(std::size_t camera, std::size_t unit) const { return (row(camera)[unit >> 6] >> (unit & 63)) & 1u; }
  void set(std::size_t camera, std::size_t unit) { row(camera)[unit >> 6] |= std::uint64_t{1} << (unit & 63); }
  /// Set bits of a row.
  std::size_t count(std::size_t camera) const;
  bool operator==(const Bitfields& o) const { return units == o.units && cameras == o.cameras && words == o.words; }
};

/// Calls `f(unit)` for every set bit of `words_per_row` words, in increasing order.
template <typename F>
void for_each_set_bit(const std::uint64_t* words, std::size_t count, F&& f) {
  for (std::size_t w = 0; w < count; ++w) {
    for (std::uint64_t bits = words[w]; bits != 0; bits &= bits - 1) {
      f(w * 64 + static_cast<std::size_t>(__builtin_ctzll(bits)));
    }
  }
}

struct BitfieldOptions {
  /// Zhang & Turk's fix for faces too thin or small to own a pixel centre: a face turned
  /// toward the camera is set when one of its vertices is within 1.5 pixels of depth of the
  /// depth buffer at one of the 4 pixel centres around it.
  bool depth_test = true;
  bool neighbour_fill = false;
  /// Empty, or one flag per input face: 1 = transparent.
  std::vector<std::uint8_t> transparent;
};

class BitfieldRecorder final : public FrameConsumer {
 public:
  /// `scene`: what the frames show; `scene_face_input[t]`: the input face that its face t is
  /// (part of); `partition` maps input faces to units; `cameras`: rows to hold (the whole
  /// set, whatever is rendered). `mesh`, `scene` and `partition` are kept by reference and
  /// must outlive the recorder (temporaries are refused).
  BitfieldRecorder(const Mesh& mesh, const RenderScene& scene, std::vector<std::uint32_t> scene_face_input,
                   const PatchPartition& partition, std::size_t cameras, const BitfieldOptions& options);
  BitfieldRecorder(const Mesh&&, const RenderScene&, std::vector<std::uint32_t>, const PatchPartition&, std::size_t,
                   const BitfieldOptions&) = delete;
  BitfieldRecorder(const Mesh&, const RenderScene&&, std::vector<std::uint32_t>, const PatchPartition&, std::size_t,
                   const BitfieldOptions&) = delete;
  BitfieldRecorder(const Mesh&, const RenderScene&, std::vector<std::uint32_t>, const PatchPartition&&, std::size_t,
                   const BitfieldOptions&) = delete;

  void begin(unsigned workers) override;
  void consume(const Frame& frame, std::size_t camera, unsigned worker) override;
  /// The rows, with transparent units set in every one.
  Bitfields finish();

 private:
  struct Worker {
    std::vector<std::uint32_t> seen_in_frame;  // per input face: number of the last frame it owned a pixel in
    std::uint32_t frame_number = 0;
    std::vector<std::uint8_t> vertex_visible;  // depth test: per scene vertex, this frame
  };
  const Mesh& mesh_;
  const std::vector<Face>& scene_faces_;
  std::vector<std::uint32_t> scene_face_input_;
  const PatchPartition& partition_;
  BitfieldOptions options_;
  Bitfields bits_;
  std::vector<std::vector<std::uint32_t>> neighbours_;  // only with neighbour fill
  std::vector<std::array<float, 3>> normals_;           // with neighbour fill or the depth test
  std::vector<Worker> workers_;
};

/// Renders `mesh` (without its transparent faces) from every camera with `renderer` and
/// records its bitfields for `partition`.
Bitfields record_bitfields(const Mesh& mesh, const PatchPartition& partition, const CameraSet& cameras,
                           Renderer& renderer, const BitfieldOptions& options, RenderObserver* observer = nullptr);

/// Patch bitfields from face bitfields: a patch is set when any of its faces is (exactly
/// what rendering the patches would give, since a patch owns the pixels its faces own).
Bitfields patch_bitfields_from_faces(const Bitfields& faces, const PatchPartition& partition);

/// Reads a transparent-face list: face indices separated by white space, '#' comments.
/// Throws IoError naming the file and line for a bad or out-of-range index.
std::vector<std::uint8_t> read_face_list(const std::string& path, std::size_t faces);

}  // namespace visimp
