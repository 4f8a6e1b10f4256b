// SVG line plots (see svg_plot.h). Plain SVG 1.1, no scripts or external styles, so any
// browser or document pipeline shows it.
#include "visimp/report/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace visimp {
namespace {

constexpr double kWidth = 640, kHeight = 420, kLeft = 70, kRight = 160, kTop = 40, kBottom = 50;
const char* const kColors[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b"};

std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", v);
  return buffer;
}

struct Axis {
  bool log = false;
  double lo = 0, hi = 1;
  double transform(double v) const { return log ? std::log10(v) : v; }
  bool accepts(double v) const { return std::isfinite(v) && (!log || v > 0); }
  double fraction(double v) const { return (transform(v) - transform(lo)) / (transform(hi) - transform(lo)); }
  std::vector<double> ticks() const {
    std::vector<double> t;
    if (log) {
      for (double p = std::floor(std::log10(lo)); p <= std::ceil(std::log10(hi)); ++p) {
        const double v = std::pow(10.0, p);
        if (v >= lo * 0.999 && v <= hi * 1.001) t.push_back(v);
      }
      if (t.size() < 2) t = {lo, hi};
    } else {
      for (int i = 0; i <= 5; ++i) t.push_back(lo + (hi - lo) * i / 5.0);
    }
    return t;
  }
};

// Range of the accepted values, widened a little; a log axis spans whole decades if narrow.
Axis make_axis(bool log, const std::vector<double>& values) {
  Axis axis;
  axis.log = log;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (double v : values) {
    if (!axis.accepts(v)) continue;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  if (!(lo <= hi)) {
    lo = log ? 1 : 0;
    hi = log ? 10 : 1;
  }
  if (log) {
    lo /= 1.3;  // keep points off the frame
    hi *= 1.3;
    if (hi / lo < 10) {
      lo = std::pow(10.0, std::floor(std::log10(lo)));
      hi = std::pow(10.0, std::ceil(std::log10(hi)));
      if (lo == hi) hi = lo * 10;
    }
  } else {
    const double pad = hi > lo ? 0.05 * (hi - lo) : (std::abs(hi) > 0 ? 0.1 * std::abs(hi) : 1.0);
    lo = lo >= 0 && lo - pad < 0 ? 0 : lo - pad;
    hi += pad;
  }
  axis.lo = lo;
  axis.hi = hi;
  return axis;
}

}  // namespace

void SvgPlot::write(std::ostream& out) const {
  std::vector<double> xs, ys;
  for (const PlotSeries& s : series) {
    for (const auto& [x, y] : s.points) {
      xs.push_back(x);
      ys.push_back(y);
    }
  }
  const Axis ax = make_axis(log_x, xs), ay = make_axis(log_y, ys);
  const double plot_w = kWidth - kLeft - kRight, plot_h = kHeight - kTop - kBottom;
  auto px = [&](double x) { return kLeft + ax.fraction(x) * plot_w; };
  auto py = [&](double y) { return kTop + (1 - ay.fraction(y)) * plot_h; };

  out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kWidth << "\" height=\"" << kHeight
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  out << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  out << "<text x=\"" << kWidth / 2 << "\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">" << xml_escape(title)
      << "</text>\n";
  out << "<rect x=\"" << kLeft << "\" y=\"" << kTop << "\" width=\"" << plot_w << "\" height=\"" << plot_h
      << "\" fill=\"none\" stroke=\"black\"/>\n";
  for (double t : ax.ticks()) {
    out << "<line x1=\"" << px(t) << "\" y1=\"" << kTop + plot_h << "\" x2=\"" << px(t) << "\" y2=\"" << kTop
        << "\" stroke=\"#ddd\"/><text x=\"" << px(t) << "\" y=\"" << kTop + plot_h + 16
        << "\" text-anchor=\"middle\">" << number(t) << "</text>\n";
  }
  for (double t : ay.ticks()) {
    out << "<line x1=\"" << kLeft << "\" y1=\"" << py(t) << "\" x2=\"" << kLeft + plot_w << "\" y2=\"" << py(t)
        << "\" stroke=\"#ddd\"/><text x=\"" << kLeft - 6 << "\" y=\"" << py(t) + 4 << "\" text-anchor=\"end\">"
        << number(t) << "</text>\n";
  }
  out << "<text x=\"" << kLeft + plot_w / 2 << "\" y=\"" << kHeight - 12 << "\" text-anchor=\"middle\">"
      << xml_escape(x_label) << "</text>\n";
  out << "<text transform=\"translate(16," << kTop + plot_h / 2 << ") rotate(-90)\" text-anchor=\"middle\">"
      << xml_escape(y_label) << "</text>\n";
  for (std::size_t i = 0; i < series.size(); ++i) {
    const PlotSeries& s = series[i];
    const char* color = kColors[i % (sizeof kColors / sizeof kColors[0])];
    std::string path;
    for (std::size_t k = 0; k < s.points.size(); ++k) {
      const auto [x, y] = s.points[k];
      if (!ax.accepts(x) || !ay.accepts(y)) continue;
      path += (path.empty() ? "M" : " L") + number(px(x)) + " " + number(py(y));
      out << "<circle cx=\"" << px(x) << "\" cy=\"" << py(y) << "\" r=\"3.5\" fill=\"" << color << "\"/>\n";
      if (k < s.point_labels.size()) {
        out << "<text x=\"" << px(x) + 6 << "\" y=\"" << py(y) - 6 << "\" font-size=\"10\">"
            << xml_escape(s.point_labels[k]) << "</text>\n";
      }
    }
    out << "<path d=\"" << path << "\" fill=\"none\" stroke=\"" << color << "\" stroke-width=\"1.5\"/>\n";
    const double ly = kTop + 10 + 18.0 * static_cast<double>(i);
    out << "<rect x=\"" << kLeft + plot_w + 12 << "\" y=\"" << ly - 8 << "\" width=\"10\" height=\"10\" fill=\""
        << color << "\"/><text x=\"" << kLeft + plot_w + 28 << "\" y=\"" << ly + 1 << "\">" << xml_escape(s.label)
        << "</text>\n";
  }
  out << "</svg>\n";
}

std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '&') out += "&amp;";
    else if (c == '"') out += "&quot;";
    else out += c;
  }
  return out;
}

}  // namespace visimp
