// Drawing many meshes into one shaded grey frame (the walk's frames, and the projective
// textures captured while building cells): a RenderSet packs meshes as groups, each with a
// bounding sphere for frustum culling, its own grey albedo and, for LOD meshes, optional
// projective textures (textures.h). Shading is two-sided Lambert under a fixed light, with
// normals smoothed within a crease angle (or per face), so what a frame shows does not depend
// on a face's winding; luminance Y is the grey level itself.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "visimp/cells/scene.h"
#include "visimp/cells/textures.h"
#include "visimp/core/mesh.h"
#include "visimp/render/perspective.h"

namespace visimp {

enum class Shading { flat, smooth };

struct RenderSet {
  struct Group {
    std::uint32_t first_face = 0, faces = 0;
    Vec3 centre;
    double radius = 0;
    std::vector<ProjectiveTexture> textures;  ///< empty: shaded, not textured
  };
  std::vector<std::array<float, 3>> positions;
  std::vector<Face> faces;
  std::vector<std::array<float, 3>> face_normals;
  std::vector<std::array<std::array<float, 3>, 3>> corner_normals;  ///< per face, smoothed within a crease angle
  std::vector<float> face_albedo;
  std::vector<std::uint32_t> face_group;
  std::vector<Group> groups;
  /// Adds `faces` of `mesh` (all when null) as one group, in the colour of scene object `object`;
  /// corner normals are the mesh's own (area-weighted over all its faces, within 40° of the face).
  void add(const Mesh& mesh, const std::vector<std::uint32_t>* faces, std::uint32_t object);
  /// Call once after the last add(): face normals.
  void finish();
  /// Appends another finished set's groups (textures included).
  void append(const RenderSet& other);
};
/// The whole scene, one group per object.
RenderSet full_scene_set(const Scene& scene);

struct FrameImage {
  int resolution = 0;
  std::vector<std::uint8_t> y;  ///< luminance, rows bottom to top
};
/// The grey of pixels that show nothing.
inline constexpr std::uint8_t kBackgroundGrey = 200;

/// Draws the groups of `set` whose spheres meet the view frustum (all with `cull` false) and
/// shades them; a group with textures takes its grey from them where they see the point
/// (`textured`), blended by how close each texture's eye is to the ray. Returns the faces
/// drawn. `depth`, when given, receives each pixel's distance along the view direction
/// (infinity for background).
std::size_t render_frame(const RenderSet& set, const PerspectiveView& view, bool cull, Shading shading, bool textured,
                         PerspectiveRasterizer& raster, PerspectiveFrame& scratch, FrameImage& out,
                         std::vector<float>* depth = nullptr);
/// A projective texture of `object` (drawn whole, smooth-shaded) seen from `eye`, looking at
/// `centre` with a field of view that just holds the sphere of `radius` there, in a
/// `resolution`² image cropped to what shows the object.
ProjectiveTexture capture_texture(const RenderSet& object, const Vec3& eye, const Vec3& centre, double radius,
                                  int resolution);
/// PSNR of `approx` against `reference` in dB (infinity for identical images).
double psnr(const FrameImage& reference, const FrameImage& approx);

}  // namespace visimp
