// The files of `visimp compare` (docs/compare.md lists them and every column).
#include <filesystem>
#include <sstream>

#include "visimp/compare/compare.h"
#include "visimp/core/errors.h"
#include "visimp/io/atomic_file.h"
#include "visimp/io/mesh_io.h"
#include "visimp/render/image.h"
#include "visimp/report/json.h"
#include "visimp/report/svg_plot.h"

namespace visimp {
namespace {

struct MethodView {
  const char* name;
  const std::vector<CompareLevel>* levels;
  double extra_seconds;  // added to each level's time: VG needs the visibility first
};

std::vector<MethodView> methods(const CompareResult& r) {
  return {{"QB", &r.qb, 0.0}, {"VG", &r.vg, r.visibility_from_quality ? 0.0 : r.seconds_visibility}};
}

std::string level_mesh_name(const char* method, const CompareLevel& level) {
  return std::string(method[0] == 'Q' ? "qb_" : "vg_") + std::to_string(level.faces) + ".ply";
}

void write_text(const std::string& path, const std::string& text, std::vector<std::string>& written) {
  AtomicFileWriter file(path);
  file.stream() << text;
  file.commit();
  written.push_back(path);
}

std::string csv(const CompareResult& r) {
  std::ostringstream s;
  s.precision(9);
  s << "method,target,faces,seconds_simplify,seconds_visibility,seconds_total,hausdorff,hausdorff_relative,"
       "mean_a_to_b_relative,mean_b_to_a_relative,rms_relative,visible_mean_relative,visible_rms_relative,"
       "visible_max_relative,image_rms,image_rms_per_pixel,seconds_metro,seconds_image,stop_reason\n";
  for (const MethodView& m : methods(r)) {
    for (const CompareLevel& l : *m.levels) {
      const SurfaceDistance& d = l.distance;
      s << m.name << ',' << l.target << ',' << l.faces << ',' << l.seconds_simplify << ',' << m.extra_seconds << ','
        << l.seconds_simplify + m.extra_seconds << ',' << d.hausdorff << ',' << d.hausdorff / r.diagonal << ','
        << d.a_to_b.mean / r.diagonal << ',' << d.b_to_a.mean / r.diagonal << ',' << d.rms / r.diagonal << ','
        << d.visible.mean / r.diagonal << ',' << d.visible.rms / r.diagonal << ',' << d.visible.max / r.diagonal << ','
        << l.image.rms << ',' << l.image.rms_per_pixel << ',' << l.seconds_metro << ',' << l.seconds_image << ','
        << to_string(l.stop_reason) << '\n';
    }
  }
  return s.str();
}

std::string json(const CompareResult& r, const std::string& input_name) {
  std::ostringstream s;
  JsonWriter j(s);
  j.begin_object()
      .field("input", input_name)
      .field("faces_in", r.faces_in)
      .field("bbox_diagonal", r.diagonal)
      .field("relative_to", "bounding-box diagonal of the input")
      .field("mesh_visibility", r.visibility.mesh)
      .field("visibility_from_quality", r.visibility_from_quality)
      .field("visibility_exponent", r.visibility_exponent)
      .field("crease_visibility", r.crease_visibility)
      .field("hidden_faces", r.visibility.stats.hidden_faces)
      .field("hidden_area_fraction", r.visibility.stats.hidden_area_fraction)
      .field("less_image_error_with_vg_percent", r.less_image_error_percent);
  j.key("seconds").begin_object()
      .field("visibility", r.seconds_visibility)
      .field("qb", r.seconds_qb)
      .field("vg", r.seconds_vg)
      .field("tie_noise", r.seconds_tie_noise)
      .end_object();
  // Per level, VG's lead over QB and, when measured, the near-tie runs that say whether it
  // is more than the order of near-equal collapses.
  j.field("tie_noise_runs", r.tie_noise_percent.empty() ? std::size_t(0) : r.tie_noise_percent.front().size());
  j.key("per_level").begin_array();
  for (std::size_t i = 0; i < r.targets.size(); ++i) {
    j.begin_object()
        .field("target", r.targets[i])
        .field("less_image_error_with_vg_percent", r.less_image_error_percent_per_level[i]);
    if (i < r.tie_noise_percent.size()) {
      j.key("tie_noise_percent").begin_array();
      for (double p : r.tie_noise_percent[i]) j.value(p);
      j.end_array();
      j.field("tie_noise_verdict", to_string(tie_noise_verdict(r, i)));
    }
    j.end_object();
  }
  j.end_array();
  j.key("levels").begin_array();
  for (const MethodView& m : methods(r)) {
    for (const CompareLevel& l : *m.levels) {
      const SurfaceDistance& d = l.distance;
      j.begin_object()
          .field("method", m.name[0] == 'Q' ? "qb" : "vg")
          .field("target", l.target)
          .field("faces", l.faces)
          .field("stop_reason", to_string(l.stop_reason))
          .field("mesh", level_mesh_name(m.name, l));
      j.key("seconds").begin_object()
          .field("simplify", l.seconds_simplify)
          .field("visibility", m.extra_seconds)
          .field("total", l.seconds_simplify + m.extra_seconds)
          .field("metro", l.seconds_metro)
          .field("image", l.seconds_image)
          .end_object();
      j.key("geometric").begin_object()
          .field("hausdorff", d.hausdorff)
          .field("hausdorff_relative", d.hausdorff / r.diagonal)
          .field("mean_a_to_b", d.a_to_b.mean)
          .field("mean_b_to_a", d.b_to_a.mean)
          .field("rms", d.rms)
          .field("rms_relative", d.rms / r.diagonal)
          .field("visible_mean", d.visible.mean)
          .field("visible_rms", d.visible.rms)
          .field("visible_max", d.visible.max)
          .field("samples_per_direction", d.a_to_b.face_samples)
          .end_object();
      j.key("image").begin_object()
          .field("rms", l.image.rms)
          .field("rms_per_pixel", l.image.rms_per_pixel)
          .field("views", l.image.views)
          .field("resolution", l.image.resolution)
          .field("supersample", l.image.supersample)
          .end_object();
      j.end_object();
    }
  }
  j.end_array();
  j.end_object();
  s << "\n";
  return s.str();
}

// One plot: `value` of each level against faces (log x) or against seconds.
std::string plot(const CompareResult& r, const std::string& title, const std::string& y_label, bool against_seconds,
                 const std::vector<std::pair<std::string, double (*)(const CompareLevel&, double)>>& values) {
  SvgPlot p;
  p.title = title;
  p.x_label = against_seconds ? "seconds (VG includes the visibility)" : "faces";
  p.y_label = y_label;
  p.log_x = true;
  for (const auto& [suffix, value] : values) {
    for (const MethodView& m : methods(r)) {
      PlotSeries series{std::string(m.name) + suffix, {}, {}};
      for (const CompareLevel& l : *m.levels) {
        const double x = against_seconds ? l.seconds_simplify + m.extra_seconds : double(l.faces);
        series.points.emplace_back(x, value(l, r.diagonal));
        if (against_seconds) series.point_labels.push_back(std::to_string(l.faces));
      }
      p.series.push_back(series);
    }
  }
  std::ostringstream s;
  p.write(s);
  return s.str();
}

double image_rms(const CompareLevel& l, double) { return l.image.rms; }
double hausdorff_relative(const CompareLevel& l, double diagonal) { return l.distance.hausdorff / diagonal; }
double rms_relative(const CompareLevel& l, double diagonal) { return l.distance.rms / diagonal; }
double visible_rms_relative(const CompareLevel& l, double diagonal) { return l.distance.visible.rms / diagonal; }

RgbImage side_by_side(const std::vector<RgbImage>& images) {
  RgbImage out;
  out.height = images.front().height;
  for (const RgbImage& i : images) out.width += i.width;
  out.rgb.assign(std::size_t(out.width) * std::size_t(out.height) * 3, 255);
  int x0 = 0;
  for (const RgbImage& i : images) {
    for (int y = 0; y < i.height; ++y)
      std::copy_n(i.rgb.begin() + std::ptrdiff_t(std::size_t(y) * std::size_t(i.width) * 3), std::size_t(i.width) * 3,
                  out.rgb.begin() + std::ptrdiff_t((std::size_t(y) * std::size_t(out.width) + std::size_t(x0)) * 3));
    x0 += i.width;
  }
  return out;
}

RgbImage grey_picture(const Mesh& m, int size) {
  return render_face_colors(m, std::vector<Rgb>(m.num_faces(), Rgb{200, 200, 200}), size);
}

// VG's lead per level and, with near-tie runs, where it lies against their spread.
std::string per_level_table(const CompareResult& r) {
  const bool noise = !r.tie_noise_percent.empty();
  std::ostringstream s;
  s.precision(3);
  s << "<table><tr><th>target faces</th><th>% less image error with VG</th>";
  if (noise) s << "<th>near-tie runs (V in [0.99, 1]) vs QB, %</th><th>VG's lead is</th>";
  s << "</tr>\n";
  for (std::size_t i = 0; i < r.targets.size(); ++i) {
    s << "<tr><td>" << r.targets[i] << "</td><td>" << r.less_image_error_percent_per_level[i] << "</td>";
    if (noise) {
      s << "<td>";
      for (std::size_t k = 0; k < r.tie_noise_percent[i].size(); ++k) s << (k ? ", " : "") << r.tie_noise_percent[i][k];
      s << "</td><td>" << to_string(tie_noise_verdict(r, i)) << " the near-tie spread</td>";
    }
    s << "</tr>\n";
  }
  s << "</table>\n";
  if (noise) {
    s << "<p>Near-tie runs: VG with V drawn from [0.99, 1] orders collapses as QB does except where costs are "
         "within 2%; how far they land from QB is how much the order of near-equal collapses alone moves a "
         "level.</p>\n";
  }
  return s.str();
}

std::string html(const CompareResult& r, const std::string& input_name, std::size_t middle) {
  std::ostringstream s;
  s.precision(4);
  s << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>visimp compare: " << xml_escape(input_name)
    << "</title>\n<style>body{font-family:sans-serif;margin:2em;max-width:72em}table{border-collapse:collapse}"
       "td,th{border:1px solid #bbb;padding:.2em .6em;text-align:right}img{max-width:100%}</style></head><body>\n"
    << "<h1>QB vs VG: " << xml_escape(input_name) << "</h1>\n"
    << "<p>" << r.faces_in << " faces; V(M) = " << r.visibility.mesh << "; hidden area "
    << 100.0 * r.visibility.stats.hidden_area_fraction << "%; visibility " << r.seconds_visibility
    << " s; QB run " << r.seconds_qb << " s; VG run " << r.seconds_vg << " s.</p>\n"
    << "<p><b>VG has " << r.less_image_error_percent
    << "% less image error than QB</b> (mean over the levels, Zhang &amp; Turk Table 2).</p>\n";
  if (const std::string note = unreached_levels_note(r); !note.empty()) s << "<p><b>Note:</b> " << xml_escape(note) << ".</p>\n";
  s << per_level_table(r)
    << "<table><tr><th>method</th><th>faces</th><th>seconds</th><th>image RMS</th><th>Hausdorff / diag</th>"
       "<th>RMS / diag</th><th>visible RMS / diag</th><th>mesh</th></tr>\n";
  for (const MethodView& m : methods(r)) {
    for (const CompareLevel& l : *m.levels) {
      const std::string mesh = level_mesh_name(m.name, l);
      s << "<tr><td>" << m.name << "</td><td>" << l.faces << "</td><td>" << l.seconds_simplify + m.extra_seconds
        << "</td><td>" << l.image.rms << "</td><td>" << l.distance.hausdorff / r.diagonal << "</td><td>"
        << l.distance.rms / r.diagonal << "</td><td>" << l.distance.visible.rms / r.diagonal << "</td><td><a href=\""
        << mesh << "\">" << mesh << "</a></td></tr>\n";
    }
  }
  s << "</table>\n<h2>Errors against faces</h2>\n<img src=\"image_error_vs_faces.svg\"> "
       "<img src=\"geometric_error_vs_faces.svg\">\n<h2>Errors against seconds</h2>\n"
       "<img src=\"image_error_vs_seconds.svg\"> <img src=\"geometric_error_vs_seconds.svg\">\n"
    << "<h2>Original | QB | VG at " << r.qb[middle].faces << " / " << r.vg[middle].faces << " faces</h2>\n"
    << "<img src=\"side_by_side.png\">\n<h2>Visibility (white: hidden, red → yellow → green: seen)</h2>\n"
       "<img src=\"visibility.png\">\n<p>Data: <a href=\"results.csv\">results.csv</a>, "
       "<a href=\"results.json\">results.json</a>.</p>\n</body></html>\n";
  return s.str();
}

}  // namespace

std::vector<std::string> write_compare_report(const CompareResult& r, const Mesh& input, const std::string& input_name,
                                              const std::string& directory) {
  namespace fs = std::filesystem;
  // All or nothing: the files go to a staging directory that replaces `directory` at the end,
  // so an interrupted or failed run leaves the previous report whole.
  StagedDirectory staged(directory);
  const fs::path dir(staged.path());
  auto at = [&](const std::string& name) { return (dir / name).string(); };
  std::vector<std::string> written;
  write_text(at("results.csv"), csv(r), written);
  write_text(at("results.json"), json(r, input_name), written);
  write_text(at("image_error_vs_faces.svg"),
             plot(r, "Image error (eq. 5.11) vs faces", "image RMS error", false, {{"", image_rms}}), written);
  write_text(at("image_error_vs_seconds.svg"),
             plot(r, "Image error (eq. 5.11) vs seconds", "image RMS error", true, {{"", image_rms}}), written);
  const std::vector<std::pair<std::string, double (*)(const CompareLevel&, double)>> geometric = {
      {" Hausdorff", hausdorff_relative}, {" RMS", rms_relative}, {" visible RMS", visible_rms_relative}};
  write_text(at("geometric_error_vs_faces.svg"),
             plot(r, "Geometric error vs faces", "error / bounding-box diagonal", false, geometric), written);
  write_text(at("geometric_error_vs_seconds.svg"),
             plot(r, "Geometric error vs seconds", "error / bounding-box diagonal", true, geometric), written);
  for (const MethodView& m : methods(r)) {
    for (const CompareLevel& l : *m.levels) {
      write_mesh(l.mesh, at(level_mesh_name(m.name, l)));
      written.push_back(at(level_mesh_name(m.name, l)));
    }
  }
  write_png(at("visibility.png"), render_visibility_map(input, r.visibility.face, 640));
  written.push_back(at("visibility.png"));
  const std::size_t middle = r.targets.size() / 2;
  write_png(at("side_by_side.png"),
            side_by_side({grey_picture(input, 480), grey_picture(r.qb[middle].mesh, 480), grey_picture(r.vg[middle].mesh, 480)}));
  written.push_back(at("side_by_side.png"));
  write_text(at("report.html"), html(r, input_name, middle), written);
  staged.commit();
  for (std::string& path : written) path = (fs::path(directory) / fs::path(path).filename()).string();
  return written;
}

}  // namespace visimp
