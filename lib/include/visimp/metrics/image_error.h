// Image RMS error between two meshes (Zhang & Turk 2002, §5, eq. 5.11): both are rendered
// flat-shaded from the 20 vertices of a dodecahedron around the bounding sphere of A (the
// reference; of A and B together when a vertex of B lies outside it), and the pixel
// intensities compared. Framing on A alone means every B measured against the same A sees
// the very same images of A.
//
//   D_n = Σ_pixels (I_A − I_B)²  for view n,   RMS = sqrt(Σ_n D_n)           (eq. 5.11)
//
// eq. 5.11 grows with the resolution, so a per-pixel RMS, sqrt(Σ_n D_n / (20·R²)), is
// reported beside it. Shading: one light at the camera, intensity 255·|N·R| per face
// (two-sided, so an open surface seen from behind is not black), background 0. Rendering
// uses the same frame backends as the visibility measure.
//
// Each pixel is the mean of s×s samples (box filter, s = 4 by default). Point-sampled 256²
// views alias at every silhouette and crease: the same two meshes measured at 256², 512² and
// 2048² differed by up to 6 points in "% less error with VG" (docs/metrics.md), more than the
// QB–VG differences the measure exists to show.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "visimp/core/mesh.h"
#include "visimp/render/renderer.h"

namespace visimp {

struct ImageErrorOptions {
  int resolution = 256;           ///< view width and height in pixels, 16..8192
  unsigned threads = 0;           ///< 0 = one per hardware thread
  std::string difference_prefix;  ///< non-empty: write PREFIX<n>.png, |I_A − I_B| in red, per view
  int supersample = 4;            ///< s×s samples averaged per pixel, 1..8 (1: point sampling)
};

struct ImageError {
  double rms = 0;                ///< sqrt(Σ_n D_n), intensities 0..255 (eq. 5.11)
  double rms_per_pixel = 0;      ///< sqrt(Σ_n D_n / (views · R²)), 0..255
  std::vector<double> view_rms;  ///< per view: sqrt(D_n / R²)
  int resolution = 0;
  int supersample = 0;
  std::size_t views = 0;
  double seconds = 0;
};

/// Throws UsageError for a bad resolution or supersampling factor, IoError if a difference image cannot be written.
ImageError image_error(const Mesh& a, const Mesh& b, const ImageErrorOptions& options = {});

/// A's 20 views rendered once, for measuring many B against the same A (compare's levels and
/// tie-noise runs): error_to(b) renders B alone and equals image_error(a, b, options) to the
/// bit. A B reaching outside A's bounding sphere widens the frame, and A is drawn again for it.
/// Keeps a reference to `a`, which must outlive it.
class ImageErrorReference {
 public:
  /// Throws UsageError for a bad resolution or supersampling factor.
  ImageErrorReference(const Mesh& a, const ImageErrorOptions& options = {});
  ~ImageErrorReference();
  ImageErrorReference(const ImageErrorReference&) = delete;
  ImageErrorReference& operator=(const ImageErrorReference&) = delete;

  /// `seconds` counts B's rendering and the comparison (and A's, when the frame widens).
  /// Throws IoError if a difference image cannot be written.
  ImageError error_to(const Mesh& b) const;
  /// The same, writing its difference images to PREFIX<n>.png instead of the options' prefix
  /// (none when empty): one reference, several B, each B's images named apart.
  ImageError error_to(const Mesh& b, const std::string& difference_prefix) const;

 private:
  struct Views;  // private to image_error.cpp
  const Mesh& a_;
  ImageErrorOptions options_;
  std::unique_ptr<Views> own_;
};

}  // namespace visimp
