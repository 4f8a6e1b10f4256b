// Resampling the visibility field for a viewpoint (see resample.h).
#include "visimp/field/resample.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "visimp/core/errors.h"

namespace visimp {

std::string interpolation_name(Interpolation interpolation) {
  switch (interpolation) {
    case Interpolation::Uv:
      return "uv";
    case Interpolation::St:
      return "st";
    case Interpolation::UvSt:
      return "uvst";
    default:
      return "none";
  }
}

Interpolation parse_interpolation(const std::string& name) {
  if (name == "none") return Interpolation::None;
  if (name == "uv") return Interpolation::Uv;
  if (name == "st") return Interpolation::St;
  if (name == "uvst" || name == "uv+st") return Interpolation::UvSt;
  throw UsageError("interpolation must be none, uv, st or uvst, got '" + name + "'");
}

void check_options(const ResampleOptions& options) {
  const int root = static_cast<int>(std::lround(std::sqrt(std::max(options.subsample, 0))));
  if (options.subsample < 1 || options.subsample > 1024 || root * root != options.subsample) {
    throw OptionError(&options.subsample, "ResampleOptions::subsample",
                      "must be a square in [1, 1024] (1 of k pixels: 1, 4, 9, 16, ...)");
  }
  if (options.mip < -1) throw OptionError(&options.mip, "ResampleOptions::mip", "must be -1 (auto) or a level >= 0");
}

std::vector<OptionSpec> describe_options(ResampleOptions& o) {
  return {option_spec("--subsample", "K", o.subsample, "resample 1 of K pixels (a square: 1, 4, 9, 16, ...)"),
          option_spec("--mip", "L", o.mip, "mip-map level to read (0 = the field itself, -1 = by distance)")};
}

namespace {

// One coarser level: each coarse sample keeps the ids most weighted among its (up to) 16
// children, a child's rank r counting ids − r.
std::vector<std::uint32_t> coarsen(const std::vector<std::uint32_t>& fine, int uv, int st, int ids, int cuv, int cst) {
  std::vector<std::uint32_t> out(static_cast<std::size_t>(cuv) * cuv * cst * cst * static_cast<std::size_t>(ids), 0);
  std::vector<std::pair<std::uint32_t, int>> weights;
  auto fine_index = [&](int iu, int iv, int is, int it) {
    return ((((static_cast<std::size_t>(iu) * uv + iv) * st + is) * st + it) * static_cast<std::size_t>(ids));
  };
  std::size_t k = 0;
  for (int iu = 0; iu < cuv; ++iu)
    for (int iv = 0; iv < cuv; ++iv)
      for (int is = 0; is < cst; ++is)
        for (int it = 0; it < cst; ++it, ++k) {
          weights.clear();
          for (int c = 0; c < 16; ++c) {
            const int u = std::min(2 * iu + (c & 1), uv - 1), v = std::min(2 * iv + ((c >> 1) & 1), uv - 1);
            const int s = std::min(2 * is + ((c >> 2) & 1), st - 1), t = std::min(2 * it + ((c >> 3) & 1), st - 1);
            const std::uint32_t* entry = &fine[fine_index(u, v, s, t)];
            for (int r = 0; r < ids && entry[r] != 0; ++r) {
              auto it2 =
                  std::find_if(weights.begin(), weights.end(), [&](const auto& w) { return w.first == entry[r]; });
              if (it2 == weights.end())
                weights.push_back({entry[r], ids - r});
              else
                it2->second += ids - r;
            }
          }
          std::sort(weights.begin(), weights.end(), [](const auto& a, const auto& b) {
            return a.second != b.second ? a.second > b.second : a.first < b.first;
          });
          for (int r = 0; r < ids && static_cast<std::size_t>(r) < weights.size(); ++r)
            out[k * static_cast<std::size_t>(ids) + static_cast<std::size_t>(r)] =
                weights[static_cast<std::size_t>(r)].first;
        }
  return out;
}

}  // namespace

FieldResampler::FieldResampler(const VisibilityField& field) : field_(field) {
  for (auto& row : slab_of_) row[0] = row[1] = -1;
  for (std::size_t i = 0; i < field.slabs.size(); ++i) {
    slab_of_[field.slabs[i].axis][field.slabs[i].side > 0 ? 1 : 0] = static_cast<int>(i);
  }
  int uv = field.options.uv, st = field.options.st;
  const int ids = field.options.ids;
  while (uv >= 2 && st >= 2) {
    Level level;
    level.uv = (uv + 1) / 2;
    level.st = (st + 1) / 2;
    level.samples.resize(field.slabs.size());
    for (std::size_t s = 0; s < field.slabs.size(); ++s) {
      for (std::size_t l = 0; l < field.slabs[s].starts.size(); ++l) {
        const auto& fine = levels_.empty() ? field.samples[s][l] : levels_.back().samples[s][l];
        level.samples[s].push_back(coarsen(fine, uv, st, ids, level.uv, level.st));
      }
    }
    uv = level.uv;
    st = level.st;
    levels_.push_back(std::move(level));
  }
}

const FieldResampler::Samples& FieldResampler::samples(int level, std::size_t slab, std::size_t layer) const {
  return level == 0 ? field_.samples[slab][layer] : levels_[static_cast<std::size_t>(level - 1)].samples[slab][layer];
}

ResampleResult FieldResampler::resample(const PerspectiveView& view, const ResampleOptions& options) const {
  ResampleResult out;
  resample(view, options, out);
  return out;
}

void FieldResampler::resample(const PerspectiveView& view, const ResampleOptions& options, ResampleResult& out) const {
  check_options(options);
  const std::size_t cells = field_.cells.num_cells();
  out.marked.assign(cells, 0);
  out.cells_marked = out.rays = out.rays_in_field = out.gap_cells = 0;
  out.mip_level = 0;
  const int stride = static_cast<int>(std::lround(std::sqrt(options.subsample)));
  const int size = view.resolution;
  const int ids = field_.options.ids;
  const bool interp_uv = options.interpolation == Interpolation::Uv || options.interpolation == Interpolation::UvSt;
  const bool interp_st = options.interpolation == Interpolation::St || options.interpolation == Interpolation::UvSt;

  // Per slab: the layer in front of the eye (-1: none, the box ends before one), whether a
  // gap of geometry lies between eye and that plane, and the mip level.
  struct SlabQuery {
    int layer = -1, level = 0, uv = 0, st = 0;
    double shrink = 1;
    bool gap = false, used = false;
    double gap_lo = 0, gap_hi = 0;
  };
  std::vector<SlabQuery> query(field_.slabs.size());
  for (std::size_t i = 0; i < field_.slabs.size(); ++i) {
    const Slab& slab = field_.slabs[i];
    SlabQuery& q = query[i];
    const double x = view.eye[slab.axis];
    // An eye outside the box reads layer 0: the box lies wholly ahead of it on every line
    // into the box, so nothing is between the box's side and the eye.
    const bool outside =
        !(view.eye.x >= field_.box.min.x && view.eye.x <= field_.box.max.x && view.eye.y >= field_.box.min.y &&
          view.eye.y <= field_.box.max.y && view.eye.z >= field_.box.min.z && view.eye.z <= field_.box.max.z);
    for (std::size_t k = 0; k < slab.starts.size(); ++k) {
      if (outside) {
        q.layer = 0;
        break;
      }
      if (slab.side * (x - slab.starts[k]) >= 0) {
        q.layer = static_cast<int>(k);
        break;
      }
    }
    const double box_far = slab.side > 0 ? field_.box.min[slab.axis] : field_.box.max[slab.axis];
    const double plane_ahead = q.layer >= 0 ? slab.starts[static_cast<std::size_t>(q.layer)] : box_far;
    q.gap = !outside && q.layer != 0 && slab.side * (x - box_far) > 0;
    q.gap_lo = std::min(x, plane_ahead);
    q.gap_hi = std::max(x, plane_ahead);
    int level = options.mip;
    if (level < 0) {
      // Query rays' spacing on the st plane against one st sample; clamped in double before
      // any cast (a far or degenerate view gives an infinite ratio).
      const double footprint = std::abs(x - slab.plane) * 2 * view.tan_half_fov * stride / size;
      const double sample = (slab.s_range[1] - slab.s_range[0]) / field_.options.st;
      const double ratio = footprint / sample;
      const int deepest = mip_levels() - 1;
      level = !(ratio > 1)                        ? 0
              : ratio >= std::ldexp(1.0, deepest) ? deepest
                                                  : static_cast<int>(std::floor(std::log2(ratio)));
    }
    q.level = std::min(level, mip_levels() - 1);
    q.uv = q.level == 0 ? field_.options.uv : levels_[static_cast<std::size_t>(q.level - 1)].uv;
    q.st = q.level == 0 ? field_.options.st : levels_[static_cast<std::size_t>(q.level - 1)].st;
    // Coarse sample j of level ℓ holds fine samples 2j, 2j + 1 of level ℓ − 1: positions in
    // level-0 units divided by 2^ℓ (exact also for odd counts, whose last coarse sample is half).
    q.shrink = std::ldexp(1.0, -q.level);
  }

  auto mark_sample = [&](const std::uint32_t* entry) {
    for (int r = 0; r < ids && entry[r] != 0; ++r) out.marked[entry[r] - 1] = 1;
  };
  // Per slab, what every ray needs: the eye in the slab's axes, the st plane, scales from
  // coordinates to sample units, the samples of the level and layer read. One division per ray.
  struct SlabFrame {
    double eye_a = 0, eye_s = 0, eye_t = 0, plane = 0, s0 = 0, t0 = 0, s_scale = 0, t_scale = 0;
    int s_axis = 0, t_axis = 0;
    const std::uint32_t* data = nullptr;
  };
  std::vector<SlabFrame> frames(field_.slabs.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const Slab& slab = field_.slabs[i];
    SlabFrame& f = frames[i];
    f.s_axis = slab.s_axis();
    f.t_axis = slab.t_axis();
    f.eye_a = view.eye[slab.axis];
    f.eye_s = view.eye[f.s_axis];
    f.eye_t = view.eye[f.t_axis];
    f.plane = slab.plane;
    f.s0 = slab.s_range[0];
    f.t0 = slab.t_range[0];
    f.s_scale = field_.options.st / (slab.s_range[1] - slab.s_range[0]);
    f.t_scale = field_.options.st / (slab.t_range[1] - slab.t_range[0]);
    if (query[i].layer >= 0) f.data = samples(query[i].level, i, static_cast<std::size_t>(query[i].layer)).data();
  }
  // Nearest sample (c in sample units, −0.5 .. n − 0.5) or the two around it.
  auto axis_samples = [](double c, int n, bool both, int(&out2)[2]) {
    if (!both) {
      out2[0] = out2[1] = std::clamp(static_cast<int>(c + 0.5), 0, n - 1);
    } else {
      const int lo = static_cast<int>(std::floor(c));
      out2[0] = std::clamp(lo, 0, n - 1);
      out2[1] = std::clamp(lo + 1, 0, n - 1);
    }
  };
  const int nu = interp_uv ? 2 : 1, ns = interp_st ? 2 : 1;
  const double st0 = field_.options.st, uv0 = field_.options.uv;
  const double eye[3] = {view.eye.x, view.eye.y, view.eye.z};
  const double box_lo[3] = {field_.box.min.x, field_.box.min.y, field_.box.min.z};
  const double box_hi[3] = {field_.box.max.x, field_.box.max.y, field_.box.max.z};
  for (int j = 0; j * stride < size; ++j) {
    for (int i = 0; i * stride < size; ++i) {
      ++out.rays;
      const Vec3 dv = view.pixel_ray(i * stride + 0.5 * stride - 0.5, j * stride + 0.5 * stride - 0.5);
      const double d[3] = {dv.x, dv.y, dv.z};
      const double ad[3] = {std::abs(d[0]), std::abs(d[1]), std::abs(d[2])};
      const int axis = ad[0] >= ad[1] && ad[0] >= ad[2] ? 0 : ad[1] >= ad[2] ? 1 : 2;
      const int slab_index = slab_of_[axis][d[axis] < 0 ? 1 : 0];  // travelling −a: the viewer is on the + side
      if (slab_index < 0) continue;
      SlabQuery& q = query[static_cast<std::size_t>(slab_index)];
      q.used = true;
      const SlabFrame& f = frames[static_cast<std::size_t>(slab_index)];
      if (f.data == nullptr) continue;
      const double inv = 1 / ad[axis];
      const double u = d[f.s_axis] * inv, v = d[f.t_axis] * inv;
      const double lambda = (f.plane - f.eye_a) * (d[axis] < 0 ? -inv : inv);
      const int uvn = q.uv, stn = q.st;
      const double s_units = (f.eye_s + lambda * d[f.s_axis] - f.s0) * f.s_scale;  // level-0 samples
      const double t_units = (f.eye_t + lambda * d[f.t_axis] - f.t0) * f.t_scale;
      if (!(s_units >= 0 && s_units <= st0 && t_units >= 0 && t_units <= st0)) continue;  // the line misses the box
      // The box must lie ahead of the eye on the ray, not behind it (a view looking away).
      double t_in = 0, t_out = std::numeric_limits<double>::infinity();
      for (int k = 0; k < 3; ++k) {
        const double inv_k = 1 / d[k];  // ±inf for 0: the slab test below still holds
        double ta = (box_lo[k] - eye[k]) * inv_k, tb = (box_hi[k] - eye[k]) * inv_k;
        if (ta > tb) std::swap(ta, tb);
        if (ta > t_in) t_in = ta;
        if (tb < t_out) t_out = tb;
      }
      if (!(t_in <= t_out)) continue;
      ++out.rays_in_field;
      const double cs = s_units * q.shrink - 0.5, ct = t_units * q.shrink - 0.5;
      const double cu = (u + 1) * 0.5 * uv0 * q.shrink - 0.5, cv = (v + 1) * 0.5 * uv0 * q.shrink - 0.5;
      int su[2], sv[2], ss[2], sts[2];
      axis_samples(cu, uvn, interp_uv, su);
      axis_samples(cv, uvn, interp_uv, sv);
      axis_samples(cs, stn, interp_st, ss);
      axis_samples(ct, stn, interp_st, sts);
      for (int a = 0; a < nu; ++a)
        for (int b = 0; b < nu; ++b)
          for (int c = 0; c < ns; ++c)
            for (int e = 0; e < ns; ++e) {
              const std::size_t index =
                  (((static_cast<std::size_t>(su[a]) * uvn + sv[b]) * stn + ss[c]) * stn + sts[e]) * ids;
              mark_sample(f.data + index);
            }
    }
  }

  // Gaps in front of an eye inside the box: cells there in the view frustum (conservative).
  const Vec3 planes[5] = {view.forward * view.tan_half_fov - view.right, view.forward * view.tan_half_fov + view.right,
                          view.forward * view.tan_half_fov - view.up, view.forward * view.tan_half_fov + view.up,
                          view.forward};
  for (std::size_t i = 0; i < query.size(); ++i) {
    const SlabQuery& q = query[i];
    if (!q.used || !q.gap) continue;
    const int axis = field_.slabs[i].axis;
    for (std::size_t c = 0; c < cells; ++c) {
      if (out.marked[c]) continue;
      const BoundingBox& b = field_.cells.bounds[c];
      if (b.max[axis] < q.gap_lo || b.min[axis] > q.gap_hi) continue;
      bool in_frustum = true;
      for (const Vec3& n : planes) {
        // The box corner farthest along n, relative to the eye.
        const Vec3 corner{n.x >= 0 ? b.max.x : b.min.x, n.y >= 0 ? b.max.y : b.min.y, n.z >= 0 ? b.max.z : b.min.z};
        if (dot(n, corner - view.eye) < 0) {
          in_frustum = false;
          break;
        }
      }
      if (in_frustum) {
        out.marked[c] = 1;
        ++out.gap_cells;
      }
    }
  }
  for (const SlabQuery& q : query) out.mip_level = std::max(out.mip_level, q.used ? q.level : 0);
  for (std::uint8_t m : out.marked) out.cells_marked += m;
}

std::vector<std::uint32_t> FieldResampler::faces_of(const std::vector<std::uint8_t>& marked) const {
  std::vector<std::uint32_t> out;
  const auto& face_cell = field_.cells.face_cell;
  for (std::size_t f = 0; f < face_cell.size(); ++f) {
    if (marked[face_cell[f]]) out.push_back(static_cast<std::uint32_t>(f));
  }
  return out;
}

void FieldResampler::append_cell_faces(const std::vector<std::uint8_t>& marked, std::vector<std::uint32_t>& out) const {
  const auto& off = field_.cells.cell_offsets;
  for (std::size_t c = 0; c < marked.size(); ++c) {
    if (marked[c])
      out.insert(out.end(), field_.cells.cell_faces.begin() + off[c], field_.cells.cell_faces.begin() + off[c + 1]);
  }
}

std::size_t FieldResampler::face_count(const std::vector<std::uint8_t>& marked) const {
  std::size_t n = 0;
  const auto& off = field_.cells.cell_offsets;
  for (std::size_t c = 0; c < marked.size(); ++c) n += marked[c] ? off[c + 1] - off[c] : 0;
  return n;
}

}  // namespace visimp
