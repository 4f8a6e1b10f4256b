// The image error's box filter: each output pixel sums the values of the s × s frame samples
// it covers (image_error.cpp scales the values by 1/s², so a pixel is their mean).
#pragma once

#include <cstddef>
#include <cstdint>

namespace visimp::detail {

/// Adds `sample_value(id)` of every sample with a nonzero id in the `samples` × `samples` frame
/// `ids` (row-major) to its pixel of `image`, (samples / supersample)² floats, row-major.
/// `samples` is a multiple of `supersample` (the frame is rendered at resolution × supersample).
/// Samples go in the order of a walk along each row (the sums' rounding is that order's), a
/// pixel's `supersample` samples at a time, with no division per sample.
template <class SampleValue>
void add_box_filtered(const std::uint32_t* ids, std::size_t samples, std::size_t supersample,
                      const SampleValue& sample_value, float* image) {
  const std::size_t size = samples / supersample;
  for (std::size_t y = 0; y < samples; ++y) {
    float* row = image + (y / supersample) * size;
    for (std::size_t pixel = 0; pixel < size; ++pixel)
      for (std::size_t k = 0; k < supersample; ++k) {
        const std::uint32_t id = *ids++;
        if (id == 0) continue;
        row[pixel] += static_cast<float>(sample_value(id));
      }
  }
}

}  // namespace visimp::detail
