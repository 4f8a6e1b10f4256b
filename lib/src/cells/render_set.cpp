// Render sets, shading, projective texture capture and PSNR (see render_set.h, textures.h).
#include "visimp/cells/render_set.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "visimp/core/bounding_box.h"
#include "visimp/core/content_hash.h"
#include "visimp/core/errors.h"

namespace visimp {
namespace {

constexpr double kDegree = M_PI / 180;
// A fixed light, two-sided Lambert with an ambient floor; sky and ground are the background.
constexpr float kAmbient = 0.25f, kDiffuse = 0.75f;

std::array<float, 3> to_float(const Vec3& v) {
  return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
}

float object_albedo(std::uint32_t object) {
  // A fixed grey per object, spread over [0.55, 0.95] so neighbours differ.
  std::uint64_t h = fnv1a(kFnvOffset, &object, sizeof object);
  return 0.55f + 0.4f * static_cast<float>(h % 1000) / 999.0f;
}

}  // namespace

void RenderSet::add(const Mesh& mesh, const std::vector<std::uint32_t>* subset, std::uint32_t object) {
  Group g;
  g.first_face = static_cast<std::uint32_t>(faces.size());
  // Only the vertices the faces use, in first-use order.
  std::vector<VertexIndex> remap(mesh.num_vertices(), ~VertexIndex{0});
  // Corner normals over all of the mesh's faces, also those left out (a culled subset of an
  // object shades as the whole object does), smoothed only across edges bending less than
  // kCreaseDegrees: a CAD part's sharp edges stay sharp however large its faces become.
  constexpr double kCreaseDegrees = 40;
  const double crease_cos = std::cos(kCreaseDegrees * kDegree);
  std::vector<Vec3> area(mesh.num_faces()), unit(mesh.num_faces());
  std::vector<std::uint32_t> first(mesh.num_vertices() + 1, 0), incident;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    area[f] = face_normal_unnormalized(mesh, mesh.faces[f]);
    const double length = norm(area[f]);
    unit[f] = length > 0 ? area[f] / length : Vec3{0, 0, 0};
    for (VertexIndex v : mesh.faces[f]) ++first[v + 1];
  }
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) first[v + 1] += first[v];
  incident.resize(first.back());
  {
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (std::size_t f = 0; f < mesh.num_faces(); ++f)
      for (VertexIndex v : mesh.faces[f]) incident[fill[v]++] = static_cast<std::uint32_t>(f);
  }
  BoundingBox box;
  const std::size_t count = subset ? subset->size() : mesh.num_faces();
  for (std::size_t k = 0; k < count; ++k) {
    const std::size_t fi = subset ? (*subset)[k] : k;
    const Face& f = mesh.faces[fi];
    Face g_face;
    std::array<std::array<float, 3>, 3> corners;
    for (int c = 0; c < 3; ++c) {
      const VertexIndex v = f[static_cast<std::size_t>(c)];
      VertexIndex& m = remap[v];
      if (m == ~VertexIndex{0}) {
        m = static_cast<VertexIndex>(positions.size());
        positions.push_back(to_float(mesh.positions[v]));
        box.extend(mesh.positions[v]);
      }
      g_face[static_cast<std::size_t>(c)] = m;
      Vec3 sum{0, 0, 0};
      for (std::uint32_t i = first[v]; i < first[v + 1]; ++i) {
        const std::uint32_t h = incident[i];
        if (dot(unit[h], unit[fi]) >= crease_cos) sum = sum + area[h];
      }
      const double length = norm(sum);
      corners[static_cast<std::size_t>(c)] = to_float(length > 0 ? sum / length : unit[fi]);
    }
    faces.push_back(g_face);
    corner_normals.push_back(corners);
  }
  g.faces = static_cast<std::uint32_t>(faces.size()) - g.first_face;
  g.centre = box.center();
  g.radius = g.faces ? 0.5 * box.diagonal() : 0;
  face_albedo.resize(faces.size(), object_albedo(object));
  face_group.resize(faces.size(), static_cast<std::uint32_t>(groups.size()));
  groups.push_back(g);
}

void RenderSet::finish() {
  face_normals.assign(faces.size(), {0, 0, 0});
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto& a = positions[faces[f][0]];
    const auto& b = positions[faces[f][1]];
    const auto& c = positions[faces[f][2]];
    const Vec3 n = cross(Vec3{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, Vec3{c[0] - a[0], c[1] - a[1], c[2] - a[2]});
    const double length = norm(n);
    if (length > 0) face_normals[f] = to_float(n / length);
  }
}

void RenderSet::append(const RenderSet& o) {
  const auto vertex_base = static_cast<VertexIndex>(positions.size());
  const auto face_base = static_cast<std::uint32_t>(faces.size());
  const auto group_base = static_cast<std::uint32_t>(groups.size());
  positions.insert(positions.end(), o.positions.begin(), o.positions.end());
  for (const Face& f : o.faces) faces.push_back({f[0] + vertex_base, f[1] + vertex_base, f[2] + vertex_base});
  face_normals.insert(face_normals.end(), o.face_normals.begin(), o.face_normals.end());
  corner_normals.insert(corner_normals.end(), o.corner_normals.begin(), o.corner_normals.end());
  face_albedo.insert(face_albedo.end(), o.face_albedo.begin(), o.face_albedo.end());
  for (std::uint32_t g : o.face_group) face_group.push_back(g + group_base);
  for (Group g : o.groups) {
    g.first_face += face_base;
    groups.push_back(std::move(g));
  }
}

RenderSet full_scene_set(const Scene& scene) {
  RenderSet set;
  for (std::size_t i = 0; i < scene.objects.size(); ++i)
    set.add(scene.object_mesh(i), nullptr, static_cast<std::uint32_t>(i));
  set.finish();
  return set;
}

std::size_t render_frame(const RenderSet& set, const PerspectiveView& view, bool cull, Shading shading, bool textured,
                         PerspectiveRasterizer& raster, PerspectiveFrame& frame, FrameImage& out,
                         std::vector<float>* depth) {
  // Per-group frustum test: the sphere against the four side planes and the near plane.
  const double t = view.tan_half_fov, plane_norm = std::sqrt(1 + t * t);
  std::vector<std::uint32_t> subset;
  std::size_t drawn = 0;
  bool all = true;
  for (const RenderSet::Group& g : set.groups) {
    bool keep = g.faces > 0;
    if (keep && cull) {
      const Vec3 p = g.centre - view.eye;
      const double x = dot(p, view.right), y = dot(p, view.up), z = dot(p, view.forward);
      keep = z + g.radius >= view.near && (x - t * z) / plane_norm <= g.radius &&
             (-x - t * z) / plane_norm <= g.radius && (y - t * z) / plane_norm <= g.radius &&
             (-y - t * z) / plane_norm <= g.radius;
    }
    if (!keep) {
      all = false;
      continue;
    }
    drawn += g.faces;
    for (std::uint32_t f = g.first_face; f < g.first_face + g.faces; ++f) subset.push_back(f);
  }
  raster.draw(set.positions, set.faces, all ? nullptr : &subset, view, frame);
  const int size = view.resolution;
  out.resolution = size;
  out.y.assign(static_cast<std::size_t>(size) * size, kBackgroundGrey);
  if (depth) depth->assign(out.y.size(), std::numeric_limits<float>::infinity());
  const Vec3 light_d = Vec3{0.3, 0.5, 0.8} / norm(Vec3{0.3, 0.5, 0.8});
  const float light[3] = {static_cast<float>(light_d.x), static_cast<float>(light_d.y), static_cast<float>(light_d.z)};
  const auto eye = to_float(view.eye);
  for (int j = 0; j < size; ++j) {
    for (int i = 0; i < size; ++i) {
      const std::size_t p = static_cast<std::size_t>(j) * size + i;
      const std::uint32_t id = frame.ids[p];
      if (id == 0) continue;
      const std::uint32_t f = id - 1;
      const RenderSet::Group& group = set.groups[set.face_group[f]];
      const bool use_texture = textured && !group.textures.empty();
      std::array<float, 3> n = set.face_normals[f];
      float grey = -1;
      if (shading == Shading::smooth || use_texture || depth) {
        // Where the pixel's ray meets the triangle (Möller–Trumbore): barycentrics for the
        // interpolated normal, the point for the textures and the depth.
        const Vec3 dir = view.pixel_ray(i, j);
        const float d[3] = {static_cast<float>(dir.x), static_cast<float>(dir.y), static_cast<float>(dir.z)};
        const auto& a = set.positions[set.faces[f][0]];
        const auto& b = set.positions[set.faces[f][1]];
        const auto& c = set.positions[set.faces[f][2]];
        const float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        const float s[3] = {eye[0] - a[0], eye[1] - a[1], eye[2] - a[2]};
        const float pv[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0]};
        const float det = e1[0] * pv[0] + e1[1] * pv[1] + e1[2] * pv[2];
        if (std::abs(det) > 0) {
          const float q[3] = {s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2], s[0] * e1[1] - s[1] * e1[0]};
          float u = (s[0] * pv[0] + s[1] * pv[1] + s[2] * pv[2]) / det;
          float v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / det;
          u = std::clamp(u, 0.0f, 1.0f);
          v = std::clamp(v, 0.0f, 1.0f - u);
          const float w = 1 - u - v;
          if (shading == Shading::smooth) {
            const auto& na = set.corner_normals[f][0];
            const auto& nb = set.corner_normals[f][1];
            const auto& nc = set.corner_normals[f][2];
            std::array<float, 3> m;
            for (std::size_t k = 0; k < 3; ++k) m[k] = w * na[k] + u * nb[k] + v * nc[k];
            const float length = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
            if (length > 0) n = {m[0] / length, m[1] / length, m[2] / length};
          }
          const Vec3 point{w * a[0] + u * b[0] + v * c[0], w * a[1] + u * b[1] + v * c[1],
                           w * a[2] + u * b[2] + v * c[2]};
          if (depth) (*depth)[p] = static_cast<float>(dot(point - view.eye, view.forward));
          if (use_texture) {
            // View-dependent blend: each texture that saw the point, weighted by how nearly its
            // eye looks along this ray (one texture for an SVMesh).
            const Vec3 ray = point - view.eye;
            const double ray_length = norm(ray);
            double sum = 0, weight = 0;
            for (const ProjectiveTexture& tex : group.textures) {
              float sample;
              if (!tex.sample(point, 0.02, &sample)) continue;
              const Vec3 from = point - tex.view.eye;
              const double cosine = dot(ray, from) / std::max(ray_length * norm(from), 1e-300);
              const double wt = 1 / (1.0001 - cosine);
              sum += wt * sample;
              weight += wt;
            }
            if (weight > 0) grey = static_cast<float>(sum / weight);
          }
        }
      }
      if (grey < 0) {
        const float lambert = std::abs(n[0] * light[0] + n[1] * light[1] + n[2] * light[2]);
        grey = 255.0f * set.face_albedo[f] * (kAmbient + kDiffuse * lambert);
      }
      out.y[p] = static_cast<std::uint8_t>(std::clamp(grey + 0.5f, 0.0f, 255.0f));
    }
  }
  return drawn;
}

bool ProjectiveTexture::sample(const Vec3& p, double tolerance, float* grey) const {
  const Vec3 q = p - view.eye;
  const double z = dot(q, view.forward);
  if (!(z > view.near)) return false;
  const double scale = 0.5 * view.resolution / (z * view.tan_half_fov);
  const double px = dot(q, view.right) * scale + 0.5 * view.resolution;
  const double py = dot(q, view.up) * scale + 0.5 * view.resolution;
  const double fi = std::floor(px) - x0, fj = std::floor(py) - y0;  // in double: px may be huge or NaN
  if (!(fi >= 0 && fj >= 0 && fi < width && fj < height)) return false;
  const int i = static_cast<int>(fi), j = static_cast<int>(fj);
  const std::size_t k = static_cast<std::size_t>(j) * width + i;
  if (depth[k] == kNoDepth) return false;
  const double seen = near_distance + (far_distance - near_distance) * depth[k] / 65534.0;
  // Within the tolerance, and a pixel's footprint: the LOD surface is not the original's.
  const double slack = tolerance * z + 2 * z * view.tan_half_fov * 2 / view.resolution;
  if (std::abs(seen - z) > slack) return false;
  *grey = y[k];
  return true;
}

ProjectiveTexture capture_texture(const RenderSet& object, const Vec3& eye, const Vec3& centre, double radius,
                                  int resolution) {
  const double distance = norm(centre - eye);
  const double half = distance > radius ? std::min(std::asin(radius / distance) * 1.05, 85 * kDegree) : 85 * kDegree;
  ProjectiveTexture tex;
  const double near = std::max(1e-4 * std::max(radius, 1e-30), 0.5 * (distance - radius));
  tex.view = PerspectiveView::looking_at(eye, centre, 2 * half / kDegree, resolution, near);
  PerspectiveRasterizer raster;
  PerspectiveFrame frame;
  FrameImage image;
  std::vector<float> depth;
  render_frame(object, tex.view, false, Shading::smooth, false, raster, frame, image, &depth);
  // Crop to what shows the object.
  int x0 = resolution, y0 = resolution, x1 = -1, y1 = -1;
  float lo = std::numeric_limits<float>::infinity(), hi = 0;
  for (int j = 0; j < resolution; ++j) {
    for (int i = 0; i < resolution; ++i) {
      const float d = depth[static_cast<std::size_t>(j) * resolution + i];
      if (!std::isfinite(d)) continue;
      x0 = std::min(x0, i), x1 = std::max(x1, i), y0 = std::min(y0, j), y1 = std::max(y1, j);
      lo = std::min(lo, d), hi = std::max(hi, d);
    }
  }
  if (x1 < 0) return tex;  // nothing seen: an empty texture samples nothing
  tex.x0 = x0, tex.y0 = y0, tex.width = x1 - x0 + 1, tex.height = y1 - y0 + 1;
  tex.near_distance = lo, tex.far_distance = std::max(hi, lo * 1.000001f);
  tex.y.resize(static_cast<std::size_t>(tex.width) * tex.height);
  tex.depth.resize(tex.y.size());
  for (int j = 0; j < tex.height; ++j) {
    for (int i = 0; i < tex.width; ++i) {
      const std::size_t from = static_cast<std::size_t>(j + y0) * resolution + (i + x0);
      const std::size_t to = static_cast<std::size_t>(j) * tex.width + i;
      tex.y[to] = image.y[from];
      const float d = depth[from];
      tex.depth[to] = std::isfinite(d) ? static_cast<std::uint16_t>(std::lround(
                                             65534.0 * (d - tex.near_distance) / (tex.far_distance - tex.near_distance)))
                                       : ProjectiveTexture::kNoDepth;
    }
  }
  return tex;
}

double psnr(const FrameImage& reference, const FrameImage& approx) {
  if (reference.y.size() != approx.y.size() || reference.y.empty())
    throw UsageError("psnr: images of different sizes");
  double sum = 0;
  for (std::size_t p = 0; p < reference.y.size(); ++p) {
    const double d = static_cast<double>(reference.y[p]) - approx.y[p];
    sum += d * d;
  }
  const double mse = sum / static_cast<double>(reference.y.size());
  return mse > 0 ? 10 * std::log10(255.0 * 255.0 / mse) : std::numeric_limits<double>::infinity();
}

}  // namespace visimp
