// The culling-rate / missed-pixel / frame-time study (see patch_study.h).
#include "visimp/patches/bitfield_file.h"
#include "visimp/patches/patch_study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "visimp/cameras/camera_set.h"
#include "visimp/core/bounding_box.h"
#include "visimp/core/content_hash.h"
#include "visimp/core/errors.h"
#include "visimp/core/portable_random.h"
#include "visimp/core/stopwatch.h"
#include "visimp/io/atomic_file.h"
#include "visimp/patches/view_reconstruction.h"
#include "visimp/report/json.h"
#include "visimp/report/svg_plot.h"

namespace visimp {
namespace {

using Clock = std::chrono::steady_clock;

// Seconds between consecutive frames of one worker: the draw and read-back time of a frame
// without the per-call setup (context, upload) that precedes the first.
class FrameTimer final : public FrameConsumer {
 public:
  void begin(unsigned) override { stamps_.clear(); }
  void consume(const Frame&, std::size_t, unsigned) override { stamps_.push_back(Clock::now()); }
  double seconds_per_frame() const {
    if (stamps_.size() < 2) return 0;
    return std::chrono::duration<double>(stamps_.back() - stamps_.front()).count() /
           static_cast<double>(stamps_.size() - 1);
  }

 private:
  std::vector<Clock::time_point> stamps_;
};

double time_frames(Renderer& timer, const RenderScene& scene, const Vec3& direction, std::size_t frames) {
  const CameraSet repeated{"timing", std::vector<Vec3>(frames + 1, direction)};
  FrameTimer consumer;
  timer.render(scene, repeated, 0, repeated.size(), consumer);
  return consumer.seconds_per_frame();
}

// A unit partition with its name for the tables.
struct Config {
  std::string unit;
  PatchPartition partition;
};

RenderScene subset_scene(const RenderScene& full, const std::vector<std::uint32_t>& faces) {
  RenderScene scene;
  scene.positions = full.positions;
  scene.radius = full.radius;
  scene.faces.reserve(faces.size());
  for (std::uint32_t f : faces) scene.faces.push_back(full.faces[f]);
  return scene;
}

}  // namespace

void check_options(const PatchStudyOptions& options) {
  if (options.max_level < 0 || options.max_level > SphereTessellation::kMaxLevel) {
    throw UsageError("the finest camera level must be 0..5 (6..4098 cameras)");
  }
  if (options.pixel_level > options.max_level || options.pixel_level < -1) {
    throw UsageError("the pixel-check camera level must be within the sampled levels");
  }
  if (options.viewpoints == 0) throw UsageError("the study needs at least one viewpoint");
  for (std::size_t p : options.patch_counts) {
    if (p == 0) throw UsageError("patch counts must be positive");
  }
}

std::vector<Vec3> random_directions(std::size_t count, std::uint64_t seed) {
  std::vector<Vec3> out(count);
  SplitMix64 random(seed);
  for (Vec3& d : out) {
    // Archimedes: z uniform in [-1, 1] and a uniform angle give a uniform point on the sphere.
    const double z = 2 * random.uniform() - 1, phi = 2 * M_PI * random.uniform();
    const double r = std::sqrt(std::max(0.0, 1 - z * z));
    d = {r * std::cos(phi), r * std::sin(phi), z};
  }
  return out;
}

PatchStudy run_patch_study(const Mesh& mesh, Renderer& sampler, Renderer* timer, const PatchStudyOptions& options,
                           RenderObserver* observer) {
  check_options(options);
  const auto start = Clock::now();
  PatchStudy study;
  study.faces = mesh.num_faces();
  study.resolution = sampler.resolution();
  study.sampler = sampler.name();
  study.timer = timer ? timer->name() : "";
  const int pixel_level = options.pixel_level < 0 ? options.max_level : options.pixel_level;

  // 1. One sampling: face bitfields at the finest level.
  const CameraSet finest = octahedron_cameras(options.max_level);
  const PatchPartition per_face = faces_as_patches(mesh);
  BitfieldOptions bit_options;
  bit_options.neighbour_fill = options.neighbour_fill;
  bit_options.depth_test = options.depth_test;
  auto t = Clock::now();
  const Bitfields face_bits = record_bitfields(mesh, per_face, finest, sampler, bit_options, observer);
  study.seconds_sampling = seconds_since(t);

  // 2. Unit partitions: the patch counts (those below the face count), then the faces.
  std::vector<Config> configs;
  for (std::size_t count : options.patch_counts) {
    if (count >= mesh.num_faces()) continue;
    PatchOptions patch_options;
    patch_options.count = count;
    PatchPartition partition = build_patches(mesh, patch_options);
    // Counts below the number of components all give the components: keep one of them.
    const bool repeated = std::any_of(configs.begin(), configs.end(), [&](const Config& c) {
      return c.partition.patch_count() == partition.patch_count();
    });
    if (repeated) continue;
    configs.push_back({"patches", std::move(partition)});
    study.patch_counts.push_back(count);
    study.seconds_patches.push_back(configs.back().partition.seconds);
  }
  configs.push_back({"faces", per_face});

  const std::vector<Vec3> viewpoints = random_directions(options.viewpoints, options.seed);
  const std::vector<Vec3> pixel_views = random_directions(options.pixel_views, options.seed ^ 0x5eedu);
  const BoundingBox box = bounding_box(mesh);
  const RenderScene full_scene = RenderScene::from_mesh(mesh, false, box.center(), view_radius(box));
  std::vector<Frame> full_frames;
  full_frames.reserve(pixel_views.size());
  for (const Vec3& d : pixel_views) full_frames.push_back(render_view(sampler, full_scene, d));
  std::vector<double> full_frame_seconds;
  const std::size_t timing_views = timer ? std::min<std::size_t>(pixel_views.size(), 5) : 0;
  for (std::size_t v = 0; v < timing_views; ++v) {
    full_frame_seconds.push_back(time_frames(*timer, full_scene, pixel_views[v], options.timing_frames));
  }

  for (const Config& config : configs) {
    const bool faces = config.unit == "faces";
    BitfieldSet set = make_bitfield_set(mesh, config.partition, faces, {}, study.resolution, bit_options);
    const Bitfields all_rows = faces ? Bitfields{} : patch_bitfields_from_faces(face_bits, config.partition);
    const Bitfields& rows = faces ? face_bits : all_rows;
    for (int level = 0; level <= options.max_level; ++level) {
      // Coarser octahedron levels are prefixes of the finest level's cameras.
      set.cameras = octahedron_cameras(level);
      set.bits = Bitfields(rows.units, set.cameras.size());
      std::copy_n(rows.words.begin(), set.bits.words.size(), set.bits.words.begin());
      const ViewReconstructor reconstructor(set);
      CullingPoint point{config.unit, rows.units, set.cameras.size(), 0, 1, 0};
      std::vector<std::uint64_t> joined(reconstructor.words_per_row());
      for (const Vec3& d : viewpoints) {
        reconstructor.join(d, joined.data());
        const double culled = 1 - static_cast<double>(reconstructor.face_count(joined.data())) /
                                      static_cast<double>(std::max<std::size_t>(1, mesh.num_faces()));
        point.culling_rate += culled;
        point.min_culling = std::min(point.min_culling, culled);
        point.max_culling = std::max(point.max_culling, culled);
      }
      point.culling_rate /= static_cast<double>(viewpoints.size());
      study.culling.push_back(point);

      if (level != pixel_level) continue;
      PixelCheck check{config.unit, rows.units, set.cameras.size(), pixel_views.size()};
      double timed_culled = 0;
      for (std::size_t v = 0; v < pixel_views.size(); ++v) {
        const std::vector<std::uint32_t> drawn = reconstructor.faces(pixel_views[v]);
        check.drawn_fraction +=
            static_cast<double>(drawn.size()) / static_cast<double>(std::max<std::size_t>(1, mesh.num_faces()));
        const RenderScene culled = subset_scene(full_scene, drawn);
        const Frame frame = render_view(sampler, culled, pixel_views[v]);
        const std::vector<std::uint32_t>& full_ids = full_frames[v].ids;
        std::uint64_t differing = 0;
        for (std::size_t p = 0; p < full_ids.size(); ++p) {
          const std::uint32_t shown = frame.ids[p] == 0 ? 0 : drawn[frame.ids[p] - 1] + 1;
          differing += shown != full_ids[p];
          check.depth_differing_pixels +=
              shown != full_ids[p] && std::fabs(frame.depth[p] - full_frames[v].depth[p]) > 1e-5f;
          check.mesh_pixels += full_ids[p] != 0;
        }
        check.differing_pixels += differing;
        check.max_differing_pixels = std::max(check.max_differing_pixels, differing);
        check.views_with_differences += differing > 0;
        if (v < timing_views) timed_culled += time_frames(*timer, culled, pixel_views[v], options.timing_frames);
      }
      check.drawn_fraction /= static_cast<double>(std::max<std::size_t>(1, pixel_views.size()));
      if (timing_views > 0) {
        check.seconds_per_frame_culled = timed_culled / static_cast<double>(timing_views);
        double full = 0;
        for (double s : full_frame_seconds) full += s;
        check.seconds_per_frame_full = full / static_cast<double>(timing_views);
      }
      study.pixels.push_back(check);
    }
  }
  study.seconds_total = seconds_since(start);
  return study;
}

void write_patch_study_json(const PatchStudy& study, std::ostream& out) {
  JsonWriter json(out);
  json.begin_object();
  json.field("faces", static_cast<std::uint64_t>(study.faces));
  json.field("resolution", study.resolution);
  json.field("sampler", study.sampler);
  json.field("timer", study.timer);
  json.field("seconds_sampling", study.seconds_sampling);
  json.field("seconds_total", study.seconds_total);
  json.key("patch_building").begin_array();
  for (std::size_t i = 0; i < study.patch_counts.size(); ++i) {
    json.begin_object();
    json.field("patches", static_cast<std::uint64_t>(study.patch_counts[i]));
    json.field("seconds", study.seconds_patches[i]);
    json.end_object();
  }
  json.end_array();
  json.key("culling").begin_array();
  for (const CullingPoint& c : study.culling) {
    json.begin_object();
    json.field("unit", c.unit);
    json.field("units", static_cast<std::uint64_t>(c.patches));
    json.field("cameras", static_cast<std::uint64_t>(c.cameras));
    json.field("culling_rate", c.culling_rate);
    json.field("min_culling_rate", c.min_culling);
    json.field("max_culling_rate", c.max_culling);
    json.end_object();
  }
  json.end_array();
  json.key("pixels").begin_array();
  for (const PixelCheck& p : study.pixels) {
    json.begin_object();
    json.field("unit", p.unit);
    json.field("units", static_cast<std::uint64_t>(p.patches));
    json.field("cameras", static_cast<std::uint64_t>(p.cameras));
    json.field("views", static_cast<std::uint64_t>(p.views));
    json.field("differing_pixels", p.differing_pixels);
    json.field("depth_differing_pixels", p.depth_differing_pixels);
    json.field("max_differing_pixels", p.max_differing_pixels);
    json.field("views_with_differences", static_cast<std::uint64_t>(p.views_with_differences));
    json.field("mesh_pixels", p.mesh_pixels);
    json.field("drawn_fraction", p.drawn_fraction);
    json.field("seconds_per_frame_full", p.seconds_per_frame_full);
    json.field("seconds_per_frame_culled", p.seconds_per_frame_culled);
    json.end_object();
  }
  json.end_array();
  json.end_object();
  out << '\n';
}

void write_patch_study(const PatchStudy& study, const std::string& directory) {
  namespace fs = std::filesystem;
  fs::create_directories(directory);
  {
    AtomicFileWriter file((fs::path(directory) / "study.csv").string());
    std::ostream& out = file.stream();
    out << "kind,unit,units,cameras,culling_rate,min_culling_rate,max_culling_rate,views,differing_pixels,"
           "depth_differing_pixels,"
           "max_differing_pixels,views_with_differences,mesh_pixels,drawn_fraction,seconds_per_frame_full,"
           "seconds_per_frame_culled\n";
    out.precision(9);
    for (const CullingPoint& c : study.culling) {
      out << "culling," << c.unit << ',' << c.patches << ',' << c.cameras << ',' << c.culling_rate << ','
          << c.min_culling << ',' << c.max_culling << ",,,,,,,,,\n";
    }
    for (const PixelCheck& p : study.pixels) {
      out << "pixels," << p.unit << ',' << p.patches << ',' << p.cameras << ",,,," << p.views << ','
          << p.differing_pixels << ',' << p.depth_differing_pixels << ',' << p.max_differing_pixels << ','
          << p.views_with_differences << ',' << p.mesh_pixels << ',' << p.drawn_fraction << ','
          << p.seconds_per_frame_full << ',' << p.seconds_per_frame_culled << '\n';
    }
    file.commit();
  }
  {
    AtomicFileWriter file((fs::path(directory) / "study.json").string());
    write_patch_study_json(study, file.stream());
    file.commit();
  }
  auto label = [](const std::string& unit, std::size_t units) {
    return unit == "faces" ? std::string("ID-bitfields (per face)") : std::to_string(units) + " patches";
  };
  SvgPlot by_samples{"Culling rate against samples", "cameras (octahedron levels)", "culling rate", true, false, {}};
  std::vector<std::pair<std::string, std::size_t>> series_keys;
  for (const CullingPoint& c : study.culling) {
    if (std::find(series_keys.begin(), series_keys.end(), std::make_pair(c.unit, c.patches)) == series_keys.end()) {
      series_keys.emplace_back(c.unit, c.patches);
      by_samples.series.push_back({label(c.unit, c.patches), {}, {}});
    }
    const auto k = static_cast<std::size_t>(
        std::find(series_keys.begin(), series_keys.end(), std::make_pair(c.unit, c.patches)) - series_keys.begin());
    by_samples.series[k].points.emplace_back(static_cast<double>(c.cameras), c.culling_rate);
  }
  SvgPlot by_patches{"Culling rate against patches", "patches", "culling rate", true, false, {}};
  std::vector<std::size_t> cameras;
  for (const CullingPoint& c : study.culling) {
    if (c.unit != "patches") continue;
    if (std::find(cameras.begin(), cameras.end(), c.cameras) == cameras.end()) {
      cameras.push_back(c.cameras);
      by_patches.series.push_back({std::to_string(c.cameras) + " cameras", {}, {}});
    }
    const auto k = static_cast<std::size_t>(std::find(cameras.begin(), cameras.end(), c.cameras) - cameras.begin());
    by_patches.series[k].points.emplace_back(static_cast<double>(c.patches), c.culling_rate);
  }
  for (const auto& [name, plot] :
       {std::make_pair("culling_vs_samples.svg", &by_samples), std::make_pair("culling_vs_patches.svg", &by_patches)}) {
    AtomicFileWriter file((fs::path(directory) / name).string());
    plot->write(file.stream());
    file.commit();
  }
}

}  // namespace visimp
