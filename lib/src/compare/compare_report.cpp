// The files of `visimp compare` (docs/compare.md lists them and every column).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "visimp/compare/compare.h"
#include "visimp/core/errors.h"
#include "visimp/io/atomic_file.h"
#include "visimp/io/mesh_io.h"
#include "visimp/render/image.h"
#include "visimp/report/json.h"
#include "visimp/report/option_values.h"
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

std::string json(const CompareResult& r, const std::string& input_name, const std::vector<OptionSpec>& options) {
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
      .field("quadric_weights", to_string(r.quadric_weights))
      .field("area_floor", r.area_floor)
      .field("hidden_faces", r.visibility.stats.hidden_faces)
      .field("hidden_area_fraction", r.visibility.stats.hidden_area_fraction)
      .field("less_image_error_with_vg_percent", r.less_image_error_percent);
  if (!options.empty()) {
    j.key("options");
    write_option_values(j, options);
  }
  j.key("seconds")
      .begin_object()
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
      j.key("seconds")
          .begin_object()
          .field("simplify", l.seconds_simplify)
          .field("visibility", m.extra_seconds)
          .field("total", l.seconds_simplify + m.extra_seconds)
          .field("metro", l.seconds_metro)
          .field("image", l.seconds_image)
          .end_object();
      j.key("geometric")
          .begin_object()
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
      j.key("image")
          .begin_object()
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

// A plotted error: colour tells the method, the line the metric.
struct Metric {
  const char* name;  // appended to the method's name in the legend; "" for one metric
  double (*value)(const CompareLevel& level, double diagonal);
  LineStyle line;
};

struct PlotSpec {
  std::string title, subtitle, y_label;
  std::vector<Metric> metrics;
};

const char* method_color(const MethodView& m) { return m.name[0] == 'Q' ? "#1f77b4" : "#d62728"; }

// One plot of each metric per method against faces (log x) or seconds; an axis is log when its
// values span decades (QB's and VG's RMS can be 100× apart: on a linear axis QB's is flat).
std::string plot(const CompareResult& r, const PlotSpec& spec, bool against_seconds) {
  SvgPlot p;
  p.title = spec.title;
  p.subtitle = spec.subtitle;
  p.x_label = against_seconds ? "seconds (VG includes the visibility)" : "faces";
  p.y_label = spec.y_label;
  std::vector<double> xs, ys;
  for (const Metric& metric : spec.metrics) {
    for (const MethodView& m : methods(r)) {
      PlotSeries series{std::string(m.name) + metric.name, {}, {}, method_color(m), metric.line};
      for (const CompareLevel& l : *m.levels) {
        const double x = against_seconds ? l.seconds_simplify + m.extra_seconds : double(l.faces);
        series.points.emplace_back(x, metric.value(l, r.diagonal));
        xs.push_back(x);
        ys.push_back(series.points.back().second);
        // One metric's points are labelled: the same faces on every curve would crowd them out.
        if (against_seconds && &metric == &spec.metrics.front()) series.point_labels.push_back(std::to_string(l.faces));
      }
      p.series.push_back(series);
    }
  }
  p.log_x = !against_seconds || spans_decades(xs);  // the levels are spaced evenly in log faces
  p.log_y = spans_decades(ys);
  std::ostringstream s;
  p.write(s);
  return s.str();
}

double image_rms(const CompareLevel& l, double) { return l.image.rms; }
double hausdorff_relative(const CompareLevel& l, double diagonal) { return l.distance.hausdorff / diagonal; }
double rms_relative(const CompareLevel& l, double diagonal) { return l.distance.rms / diagonal; }
double visible_rms_relative(const CompareLevel& l, double diagonal) { return l.distance.visible.rms / diagonal; }
double visible_mean_relative(const CompareLevel& l, double diagonal) { return l.distance.visible.mean / diagonal; }

// What "image RMS" is, in this run's numbers (image_error.h, eq. 5.11): not a per-pixel value,
// it grows with the resolution.
std::string image_rms_definition(const CompareResult& r) {
  const ImageError& e = r.qb.front().image;
  return "√Σ(I_A − I_B)² over " + std::to_string(e.views) + " views of " + std::to_string(e.resolution) +
         "² px, I in grey levels 0..255, " + std::to_string(e.supersample) + "×" + std::to_string(e.supersample) +
         " samples a pixel";
}

// sqrt(views · R²): image RMS divided by it is the RMS per pixel in grey levels.
double per_pixel_divisor(const CompareResult& r) {
  const ImageError& e = r.qb.front().image;
  return std::sqrt(double(e.views)) * double(e.resolution);
}

std::string fixed(double v, int decimals) {
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  return buffer;
}

std::string signed_percent(double v) {
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, "%+.1f", v);
  return buffer;
}

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

// The lower of the two errors in bold, so each pair's winner reads at a glance; none when
// they print alike.
std::string pair_cells(double qb, double vg) {
  const std::string q = short_number(qb), v = short_number(vg);
  auto cell = [&](const std::string& text, bool lower) {
    return std::string(lower && q != v ? "<td class=\"lower\">" : "<td>") + text + "</td>";
  };
  return cell(q, qb < vg) + cell(v, vg < qb);
}

// Per level, QB against VG: the image error and VG's lead (with the near-tie runs when
// measured), then the visible error — the geometric figure to read beside it — and the
// whole-surface Hausdorff and RMS.
std::string summary_table(const CompareResult& r) {
  const bool noise = !r.tie_noise_percent.empty();
  std::ostringstream s;
  s << "<table class=\"summary\"><tr><th rowspan=\"2\">target faces</th><th rowspan=\"2\">faces</th>"
       "<th colspan=\"3\">image RMS (eq. 5.11)</th>";
  if (noise)
    s << "<th rowspan=\"2\">near-tie runs vs QB, %</th><th rowspan=\"2\">VG's lead vs the near-tie spread</th>";
  s << "<th colspan=\"2\">visible RMS / diag</th><th colspan=\"2\">visible mean / diag</th>"
       "<th colspan=\"2\">Hausdorff / diag</th><th colspan=\"2\">RMS / diag</th></tr>\n<tr><th>QB</th><th>VG</th>"
       "<th>% less with VG</th>";
  for (int k = 0; k < 4; ++k) s << "<th>QB</th><th>VG</th>";
  s << "</tr>\n";
  const double d = r.diagonal;
  for (std::size_t i = 0; i < r.targets.size(); ++i) {
    const CompareLevel &q = r.qb[i], &v = r.vg[i];
    s << "<tr><td>" << r.targets[i] << "</td><td>"
      << (q.faces == v.faces ? std::to_string(q.faces) : std::to_string(q.faces) + " / " + std::to_string(v.faces))
      << "</td>" << pair_cells(q.image.rms, v.image.rms) << "<td>"
      << signed_percent(r.less_image_error_percent_per_level[i]) << "</td>";
    if (noise) {
      s << "<td>";
      for (std::size_t k = 0; k < r.tie_noise_percent[i].size(); ++k)
        s << (k ? ", " : "") << signed_percent(r.tie_noise_percent[i][k]);
      s << "</td><td>" << to_string(tie_noise_verdict(r, i)) << "</td>";
    }
    s << pair_cells(visible_rms_relative(q, d), visible_rms_relative(v, d))
      << pair_cells(visible_mean_relative(q, d), visible_mean_relative(v, d))
      << pair_cells(hausdorff_relative(q, d), hausdorff_relative(v, d))
      << pair_cells(rms_relative(q, d), rms_relative(v, d)) << "</tr>\n";
  }
  s << "</table>\n<p class=\"small\">Bold: the lower of QB and VG. Faces \"a / b\": QB and VG stopped at "
       "different counts. <b>Image RMS</b>: "
    << xml_escape(image_rms_definition(r)) << " (eq. 5.11, Zhang &amp; Turk 2002); divide by "
    << fixed(per_pixel_divisor(r), 0)
    << " for the RMS per pixel in grey levels (image_rms_per_pixel in results.csv). <b>Visible RMS / mean</b>: "
       "from the input's samples to the result, each weighted by its area × V. <b>Hausdorff / RMS</b>: both "
       "directions, every sample alike, seen or not. Distances are divided by the input's bounding-box diagonal ("
    << short_number(r.diagonal) << ").</p>\n";
  if (noise) {
    s << "<p class=\"small\">Near-tie runs: VG with V drawn from [0.99, 1] orders collapses as QB does except where "
         "costs are within 2%; how far they land from QB is how much the order of near-equal collapses alone moves "
         "a level.</p>\n";
  }
  return s.str();
}

// How often VG is on each side of QB, level by level; the reading paragraph quotes them.
struct LevelTally {
  std::size_t levels = 0, image_lower = 0, hausdorff_higher = 0, rms_higher = 0, visible_rms_lower = 0;
  double hausdorff_ratio = 0;                     // largest VG / QB over the levels
  double visible_max_qb = 0, visible_max_vg = 0;  // largest over the levels, relative
};

LevelTally tally_levels(const CompareResult& r) {
  LevelTally t;
  t.levels = r.targets.size();
  for (std::size_t i = 0; i < t.levels; ++i) {
    const CompareLevel &q = r.qb[i], &v = r.vg[i];
    t.image_lower += v.image.rms < q.image.rms;
    t.hausdorff_higher += v.distance.hausdorff > q.distance.hausdorff;
    t.rms_higher += v.distance.rms > q.distance.rms;
    t.visible_rms_lower += v.distance.visible.rms < q.distance.visible.rms;
    if (q.distance.hausdorff > 0)
      t.hausdorff_ratio = std::max(t.hausdorff_ratio, v.distance.hausdorff / q.distance.hausdorff);
    t.visible_max_qb = std::max(t.visible_max_qb, q.distance.visible.max / r.diagonal);
    t.visible_max_vg = std::max(t.visible_max_vg, v.distance.visible.max / r.diagonal);
  }
  return t;
}

std::string of_levels(std::size_t count, std::size_t levels) {
  return std::to_string(count) + " of " + std::to_string(levels) + " level" + (levels == 1 ? "" : "s");
}

// How both methods weighed each face's plane (the default, or what --quadric-weights and
// --area-floor chose): runs with other weights are not comparable number for number.
std::string plane_weights(const CompareResult& r) {
  if (r.quadric_weights == QuadricWeights::uniform) return "planes weighted uniformly (--quadric-weights uniform)";
  if (r.area_floor > 0)
    return "planes weighted by area + " + short_number(r.area_floor) + " x the median face area (--area-floor)";
  return "planes weighted by area";
}

// Why VG's Hausdorff and RMS can rise while its image error falls, with this run's counts, and
// the visible error named as the geometric figure to read.
std::string reading_paragraph(const CompareResult& r) {
  const LevelTally t = tally_levels(r);
  std::ostringstream s;
  s << "<p>VG weights each input face's quadric by V<sup>" << short_number(r.visibility_exponent)
    << "</sup> (eq. 5.10), so collapses among hidden and barely seen faces cost almost nothing and go first";
  const double hidden = r.visibility.stats.hidden_area_fraction;
  if (!r.visibility_from_quality && hidden < 0.005)
    s << "; this input has almost no hidden area (" << fixed(100.0 * hidden, 1)
      << "%), so VG has little to trade and both methods should stay close";
  else if (!r.visibility_from_quality)
    s << "; " << fixed(100.0 * hidden, 1) << "% of this input's area is never seen (V = 0)";
  s << ". Hausdorff distance and RMS compare the whole surfaces, hidden and seen alike: where VG has collapsed a "
       "hidden part away, the input's samples there lie far from the result, so both rise even where nothing a "
       "camera sees has changed, while the image error, which compares only what the views show, can fall. Here "
       "VG's Hausdorff distance is above QB's at "
    << of_levels(t.hausdorff_higher, t.levels);
  if (t.hausdorff_ratio > 1) s << " (up to " << short_number(t.hausdorff_ratio, 2) << "× QB's)";
  s << " and its RMS at " << of_levels(t.rms_higher, t.levels) << ", while its image error is below QB's at "
    << of_levels(t.image_lower, t.levels)
    << ". The geometric figure that matches what a viewer sees is the <b>visible error</b>: the input's samples "
       "weighted by area × V, so a hidden part that is gone costs nothing; read it beside the image error. VG's "
       "visible RMS is below QB's at "
    << of_levels(t.visible_rms_lower, t.levels);
  if (2 * t.visible_rms_lower < t.levels && t.visible_max_vg > t.visible_max_qb) {
    s << "; at the others VG moved seen surface further than QB did (the largest distance at a sample with "
         "V &gt; 0 reaches "
      << short_number(t.visible_max_vg) << " of the diagonal for VG against " << short_number(t.visible_max_qb)
      << " for QB)";
  }
  s << ".</p>\n";
  return s.str();
}

std::string headline(const CompareResult& r) {
  const double p = r.less_image_error_percent;
  return "<p><b>VG has " + fixed(std::abs(p), 2) + (p >= 0 ? "% less" : "% more") +
         " image error than QB</b> (mean over the levels of 100·(QB − VG)/QB, Zhang &amp; Turk Table 2).</p>\n";
}

// Every result with its time and mesh file.
std::string results_table(const CompareResult& r) {
  std::ostringstream s;
  s << "<table><tr><th>method</th><th>faces</th><th>seconds</th><th>image RMS</th><th>Hausdorff / diag</th>"
       "<th>RMS / diag</th><th>visible RMS / diag</th><th>visible mean / diag</th><th>mesh</th></tr>\n";
  for (const MethodView& m : methods(r)) {
    for (const CompareLevel& l : *m.levels) {
      const std::string mesh = level_mesh_name(m.name, l);
      s << "<tr><td>" << m.name << "</td><td>" << l.faces << "</td><td>"
        << short_number(l.seconds_simplify + m.extra_seconds) << "</td><td>" << short_number(l.image.rms) << "</td><td>"
        << short_number(hausdorff_relative(l, r.diagonal)) << "</td><td>" << short_number(rms_relative(l, r.diagonal))
        << "</td><td>" << short_number(visible_rms_relative(l, r.diagonal)) << "</td><td>"
        << short_number(visible_mean_relative(l, r.diagonal)) << "</td><td><a href=\"" << mesh << "\">" << mesh
        << "</a></td></tr>\n";
    }
  }
  s << "</table>\n";
  return s.str();
}

std::string html(const CompareResult& r, const std::string& input_name, std::size_t middle) {
  std::ostringstream s;
  s << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>visimp compare: " << xml_escape(input_name)
    << "</title>\n<style>body{font-family:sans-serif;margin:2em;max-width:80em}table{border-collapse:collapse;"
       "margin:.5em 0}td,th{border:1px solid #bbb;padding:.2em "
       ".5em;text-align:right}td{white-space:nowrap}th{background:#f2f2f2}"
       "td.lower{font-weight:bold}table.summary{font-size:90%}p.small{font-size:90%;color:#333;max-width:60em}p{max-"
       "width:60em}"
       "img{max-width:100%;vertical-align:top}</style></head><body>\n"
    << "<h1>QB vs VG: " << xml_escape(input_name) << "</h1>\n"
    << "<p>" << r.faces_in << " faces; V(M) = " << fixed(r.visibility.mesh, 3) << "; hidden area "
    << fixed(100.0 * r.visibility.stats.hidden_area_fraction, 1) << "%; visibility "
    << short_number(r.seconds_visibility) << " s; QB run " << short_number(r.seconds_qb) << " s; VG run "
    << short_number(r.seconds_vg) << " s; " << plane_weights(r) << ".</p>\n"
    << headline(r);
  if (const std::string note = unreached_levels_note(r); !note.empty())
    s << "<p><b>Note:</b> " << xml_escape(note) << ".</p>\n";
  s << "<h2>Reading the result</h2>\n"
    << reading_paragraph(r) << summary_table(r)
    << "<h2>Errors against faces</h2>\n<img src=\"image_error_vs_faces.svg\"> "
       "<img src=\"geometric_error_vs_faces.svg\">\n<h2>Errors against seconds</h2>\n"
       "<img src=\"image_error_vs_seconds.svg\"> <img src=\"geometric_error_vs_seconds.svg\">\n"
    << "<h2>Every result</h2>\n"
    << results_table(r) << "<h2>Original | QB | VG at " << r.qb[middle].faces << " / " << r.vg[middle].faces
    << " faces</h2>\n"
    << "<img src=\"side_by_side.png\">\n<h2>Visibility (white: hidden, red → yellow → green: seen)</h2>\n"
       "<img src=\"visibility.png\">\n<p>Data: <a href=\"results.csv\">results.csv</a>, "
       "<a href=\"results.json\">results.json</a>.</p>\n</body></html>\n";
  return s.str();
}

}  // namespace

std::vector<std::string> write_compare_report(const CompareResult& r, const Mesh& input, const std::string& input_name,
                                              const std::string& directory, const std::vector<OptionSpec>& options) {
  namespace fs = std::filesystem;
  // All or nothing: the files go to a staging directory that replaces `directory` at the end,
  // so an interrupted or failed run leaves the previous report whole.
  StagedDirectory staged(directory);
  const fs::path dir(staged.path());
  auto at = [&](const std::string& name) { return (dir / name).string(); };
  std::vector<std::string> written;
  write_text(at("results.csv"), csv(r), written);
  write_text(at("results.json"), json(r, input_name, options), written);
  const std::string image_y = "image RMS error (eq. 5.11)";
  const PlotSpec image{"Image error vs faces", image_rms_definition(r), image_y, {{"", image_rms, LineStyle::solid}}};
  const PlotSpec geometric{
      "Geometric error vs faces",
      "visible RMS: input → result, samples weighted by area × V; RMS, Hausdorff: both ways, all samples",
      "distance / bounding-box diagonal",
      {{" visible RMS", visible_rms_relative, LineStyle::solid},
       {" RMS", rms_relative, LineStyle::dashed},
       {" Hausdorff", hausdorff_relative, LineStyle::dotted}}};
  // Against seconds the points are labelled with their faces, the titles say so.
  PlotSpec image_seconds = image, geometric_seconds = geometric;
  image_seconds.title = "Image error vs seconds (point labels: faces)";
  geometric_seconds.title = "Geometric error vs seconds (point labels: faces)";
  write_text(at("image_error_vs_faces.svg"), plot(r, image, false), written);
  write_text(at("image_error_vs_seconds.svg"), plot(r, image_seconds, true), written);
  write_text(at("geometric_error_vs_faces.svg"), plot(r, geometric, false), written);
  write_text(at("geometric_error_vs_seconds.svg"), plot(r, geometric_seconds, true), written);
  for (const MethodView& m : methods(r)) {
    for (const CompareLevel& l : *m.levels) {
      write_mesh(l.mesh, at(level_mesh_name(m.name, l)));
      written.push_back(at(level_mesh_name(m.name, l)));
    }
  }
  write_png(at("visibility.png"), render_visibility_map(input, r.visibility.face, 640));
  written.push_back(at("visibility.png"));
  const std::size_t middle = r.targets.size() / 2;
  write_png(at("side_by_side.png"), side_by_side({grey_picture(input, 480), grey_picture(r.qb[middle].mesh, 480),
                                                  grey_picture(r.vg[middle].mesh, 480)}));
  written.push_back(at("side_by_side.png"));
  write_text(at("report.html"), html(r, input_name, middle), written);
  staged.commit();
  for (std::string& path : written) path = (fs::path(directory) / fs::path(path).filename()).string();
  return written;
}

}  // namespace visimp
