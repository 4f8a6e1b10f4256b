// SVG line plots (see svg_plot.h). Plain SVG 1.1, no scripts or external styles, so any
// browser or document pipeline shows it.
//
// Layout order: the title and the x axis fix the top and bottom margins, hence the plot's
// height and the y ticks; the widest y tick label fixes the left margin and the legend the
// right one, hence the width and the x ticks. Point labels go last, each where it collides
// with nothing placed before it (Heckbert's "nice numbers" for the linear ticks, Graphics
// Gems I, 1990).
#include "visimp/report/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

namespace visimp {
namespace {

constexpr double kWidth = 720, kHeight = 450;
// px; report.html shows the SVG 1:1, so these are the sizes the reader gets.
constexpr double kTitleFont = 16, kSubtitleFont = 12, kAxisFont = 14, kTickFont = 13, kLegendFont = 13, kPointFont = 11;
// Without a renderer there are no font metrics: a character is taken as 0.62 em (digits of
// DejaVu Sans and Arial are 0.56–0.64 em), so estimated boxes err on the wide side.
constexpr double kEm = 0.62;
constexpr double kMinTickGapX = 70, kMinTickGapY = 40;  // px per tick: room for a label and air
constexpr double kMarkerRadius = 3.5;
const char* const kColors[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b"};

std::string coord(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.1f", v);
  return buffer;
}

// printf pads exponents to two digits with a sign: "2e-05" → "2e-5", "1e+06" → "1e6".
std::string tidy_exponent(const std::string& s) {
  const std::size_t e = s.find('e');
  if (e == std::string::npos) return s;
  std::string exponent = s.substr(e + 1);
  const bool negative = !exponent.empty() && exponent[0] == '-';
  if (!exponent.empty() && (exponent[0] == '-' || exponent[0] == '+')) exponent.erase(0, 1);
  exponent.erase(0, std::min(exponent.find_first_not_of('0'), exponent.size() - 1));
  return s.substr(0, e) + "e" + (negative ? "-" : "") + exponent;
}

std::string printf_number(const char* format, int digits, double v) {
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, format, digits, v);
  return tidy_exponent(buffer);
}

double text_width(const std::string& s, double font) {
  std::size_t chars = 0;
  for (const char c : s) chars += (static_cast<unsigned char>(c) & 0xC0) != 0x80;  // UTF-8 code points
  return kEm * font * static_cast<double>(chars);
}

struct Box {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool overlaps(const Box& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
  bool inside(const Box& o) const { return x0 >= o.x0 && x1 <= o.x1 && y0 >= o.y0 && y1 <= o.y1; }
};

bool accepted(bool log, double v) { return std::isfinite(v) && (!log || v > 0); }

struct Axis {
  bool log = false;
  double lo = 0, hi = 1;
  std::vector<double> ticks;
  double transform(double v) const { return log ? std::log10(v) : v; }
  double fraction(double v) const { return (transform(v) - transform(lo)) / (transform(hi) - transform(lo)); }
};

// ---- ticks -------------------------------------------------------------------------------

// The smallest 1, 2 or 5 × 10^k that is at least `raw` (> 0).
double nice_step(double raw) {
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double m : {1.0, 2.0, 5.0})
    if (m * decade >= raw * (1 - 1e-9)) return m * decade;
  return 10 * decade;
}

// A 1-2-5 step giving at most max_ticks + 1 ticks, the range widened to whole steps so the
// frame ends on a tick.
Axis linear_axis(double lo, double hi, int max_ticks) {
  const double step = nice_step((hi - lo) / std::max(1, max_ticks - 1));
  Axis axis;
  const long first = std::lround(std::floor(lo / step + 1e-9)), last = std::lround(std::ceil(hi / step - 1e-9));
  axis.lo = static_cast<double>(first) * step;
  axis.hi = static_cast<double>(std::max(last, first + 1)) * step;
  for (long k = first; k <= std::max(last, first + 1); ++k) axis.ticks.push_back(static_cast<double>(k) * step);
  return axis;
}

// m × 10^p in [lo, hi] for the mantissas given, in every `every`-th decade only.
std::vector<double> log_values(double lo, double hi, const std::vector<double>& mantissas, int every) {
  std::vector<double> out;
  const int first = static_cast<int>(std::floor(std::log10(lo))), last = static_cast<int>(std::ceil(std::log10(hi)));
  for (int p = first; p <= last; ++p) {
    if (((p % every) + every) % every != 0) continue;
    for (const double m : mantissas) {
      const double v = m * std::pow(10.0, p);
      if (v >= lo * (1 - 1e-9) && v <= hi * (1 + 1e-9)) out.push_back(v);
    }
  }
  return out;
}

// The largest 1-2-5 value at most v, and the smallest at least v.
double nice_below(double v) {
  const double decade = std::pow(10.0, std::floor(std::log10(v)));
  for (const double m : {5.0, 2.0, 1.0})
    if (m * decade <= v * (1 + 1e-9)) return m * decade;
  return decade / 2;
}
double nice_above(double v) {
  const double decade = std::pow(10.0, std::floor(std::log10(v)));
  for (const double m : {1.0, 2.0, 5.0, 10.0})
    if (m * decade >= v * (1 - 1e-9)) return m * decade;
  return 10 * decade;
}

// Multiples of a 1-2-5 step inside [lo, hi], about `count` of them.
std::vector<double> linear_values(double lo, double hi, int count) {
  const double step = nice_step((hi - lo) / std::max(1, count));
  std::vector<double> out;
  for (long k = std::lround(std::ceil(lo / step - 1e-9)); static_cast<double>(k) * step <= hi * (1 + 1e-9); ++k)
    out.push_back(static_cast<double>(k) * step);
  return out;
}

// The densest of 1-2-5, whole decades, every 2nd, 3rd… decade with at most max_ticks ticks.
// A range too narrow for three of them (under a factor ~4) gets linear 1-2-5 steps instead
// (100, 150, 200), or failing that is widened once to the 1-2-5 values around it.
Axis log_axis(double lo, double hi, int max_ticks, bool widened = false) {
  Axis axis;
  axis.log = true;
  axis.lo = lo;
  axis.hi = hi;
  const std::vector<std::vector<double>> sets = {{1, 2, 5}, {1}};
  std::vector<double> denser;
  bool fitted = false;
  for (const std::vector<double>& set : sets) {
    std::vector<double> t = log_values(lo, hi, set, 1);
    if (static_cast<int>(t.size()) <= max_ticks) {
      axis.ticks = t.size() >= 2 || denser.empty() ? t : denser;  // two ticks a little too close beat one
      fitted = true;
      break;
    }
    denser = std::move(t);
  }
  // Too many decades even for whole ones: every 2nd, 3rd... (ends: one decade in `every` is
  // at most one tick). Not entered when a set fitted with no tick at all — a range between two
  // 1-2-5 values — which the fallbacks below handle (looping on it overflowed `every`).
  for (int every = 2; !fitted; ++every) {
    std::vector<double> t = log_values(lo, hi, {1}, every);
    if (static_cast<int>(t.size()) <= max_ticks) {
      axis.ticks = std::move(t);
      fitted = true;
    }
  }
  if (axis.ticks.size() >= 3 || widened) return axis;
  // Half as many as allowed: a log axis squeezes linear steps together at its top.
  std::vector<double> linear = linear_values(lo, hi, std::max(2, max_ticks / 2));
  if (linear.size() >= 3) {
    axis.ticks = std::move(linear);
    return axis;
  }
  return log_axis(nice_below(lo), nice_above(hi), max_ticks, true);
}

// Data range of the accepted values, padded so no point sits on the frame.
Axis make_axis(bool log, const std::vector<double>& values, int max_ticks) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const double v : values) {
    if (!accepted(log, v)) continue;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  if (!(lo <= hi)) {
    lo = log ? 1 : 0;
    hi = log ? 10 : 1;
  }
  max_ticks = std::max(max_ticks, 2);
  if (log) {
    const double pad = std::max(1.15, std::pow(hi / lo, 0.05));  // 5% of the span each side, in log
    return log_axis(lo / pad, hi * pad, max_ticks);
  }
  const double pad = hi > lo ? 0.04 * (hi - lo) : (std::abs(hi) > 0 ? 0.1 * std::abs(hi) : 1.0);
  lo = lo >= 0 && lo - pad < 0 ? 0 : lo - pad;  // a non-negative quantity keeps its zero
  return linear_axis(lo, hi + pad, max_ticks);
}

// One format for every label of an axis, so an axis never mixes "0.001" with "1e-4": plain
// decimals while every tick reads well so (0.001 … 99999), mantissa-exponent otherwise.
std::vector<std::string> tick_labels(const Axis& axis) {
  bool plain = true;
  for (const double v : axis.ticks) plain = plain && (v == 0 || (std::abs(v) >= 1e-3 && std::abs(v) < 1e5));
  std::vector<std::string> out;
  if (axis.log) {
    for (const double v : axis.ticks) out.push_back(printf_number(plain ? "%.*g" : "%.*e", plain ? 6 : 0, v));
    return out;
  }
  const double step = axis.ticks.size() > 1 ? axis.ticks[1] - axis.ticks[0] : 1.0;
  const int decimals = std::max(0, -static_cast<int>(std::floor(std::log10(step) + 1e-9)));
  for (const double v : axis.ticks) {
    const double rounded = std::abs(v) < step * 1e-6 ? 0.0 : v;  // k·step of 0 may come out as 1e-20
    out.push_back(plain ? printf_number("%.*f", decimals, rounded) : short_number(rounded, 2));
  }
  return out;
}

// ---- point labels ------------------------------------------------------------------------

// Spots around a marker at (x, y), best first: right, above or below on either side, then
// the same twice as far out (a crowded point may still find room there).
std::vector<Box> label_spots(double x, double y, double w, double font) {
  std::vector<Box> spots;
  const double h = font;
  for (const double gap : {kMarkerRadius + 3, 2 * kMarkerRadius + 8}) {
    const std::vector<Box> ring = {
        {x + gap, y - h / 2, x + gap + w, y + h / 2}, {x + 2, y - gap - h, x + 2 + w, y - gap},
        {x + 2, y + gap, x + 2 + w, y + gap + h},     {x - gap - w, y - h / 2, x - gap, y + h / 2},
        {x - 2 - w, y - gap - h, x - 2, y - gap},     {x - 2 - w, y + gap, x - 2, y + gap + h},
        {x - w / 2, y - gap - h, x + w / 2, y - gap}, {x - w / 2, y + gap, x + w / 2, y + gap + h}};
    spots.insert(spots.end(), ring.begin(), ring.end());
  }
  return spots;
}

bool clear_of(const Box& b, const std::vector<Box>& obstacles) {
  return std::none_of(obstacles.begin(), obstacles.end(), [&](const Box& o) { return b.overlaps(o); });
}

// The first spot inside the frame clear of every hard obstacle (labels, markers), preferring
// one clear of the lines too; none: the label is dropped.
std::optional<Box> place_label(const std::vector<Box>& spots, const Box& frame, const std::vector<Box>& hard,
                               const std::vector<Box>& lines) {
  std::optional<Box> fallback;
  for (const Box& b : spots) {
    if (!b.inside(frame) || !clear_of(b, hard)) continue;
    if (clear_of(b, lines)) return b;
    if (!fallback) fallback = b;
  }
  return fallback;
}

// Small boxes along the segment, so labels can keep off the curves.
void add_segment_boxes(double x0, double y0, double x1, double y1, std::vector<Box>& boxes) {
  const int steps = std::max(1, static_cast<int>(std::hypot(x1 - x0, y1 - y0) / 4));
  for (int i = 0; i <= steps; ++i) {
    const double t = static_cast<double>(i) / steps, x = x0 + t * (x1 - x0), y = y0 + t * (y1 - y0);
    boxes.push_back({x - 1, y - 1, x + 1, y + 1});
  }
}

const char* dash_array(LineStyle line) {
  switch (line) {
    case LineStyle::dashed:
      return "7 4";
    case LineStyle::dotted:
      return "2 3";
    case LineStyle::solid:
      break;
  }
  return "";
}

std::string series_color(const PlotSeries& s, std::size_t index) {
  return s.color.empty() ? kColors[index % (sizeof kColors / sizeof kColors[0])] : s.color;
}

// `font`, shrunk if needed so that `text` fits in `room` px.
double fitting_font(const std::string& text, double font, double room) {
  const double w = text_width(text, font);
  return w > room ? font * room / w : font;
}

// Where everything goes, from the data and the texts (the order is in the file comment).
struct Layout {
  double title_y = 0, subtitle_y = 0;
  Box frame;
  Axis ax, ay;
  std::vector<std::string> x_text, y_text;
  double legend_x = 0, swatch = 26;
  double px(double x) const { return frame.x0 + ax.fraction(x) * (frame.x1 - frame.x0); }
  double py(double y) const { return frame.y1 - ay.fraction(y) * (frame.y1 - frame.y0); }
};

Layout make_layout(const SvgPlot& plot) {
  std::vector<double> xs, ys;
  for (const PlotSeries& s : plot.series) {
    for (const auto& [x, y] : s.points) {
      xs.push_back(x);
      ys.push_back(y);
    }
  }
  Layout l;
  // Vertical: title (and subtitle), frame, tick labels, axis title.
  l.title_y = 10 + kTitleFont;
  l.subtitle_y = l.title_y + 6 + kSubtitleFont;
  l.frame.y0 = (plot.subtitle.empty() ? l.title_y : l.subtitle_y) + 16;
  l.frame.y1 = kHeight - (8 + kTickFont + 12 + kAxisFont + 10);
  l.ay = make_axis(plot.log_y, ys, static_cast<int>((l.frame.y1 - l.frame.y0) / kMinTickGapY));
  l.y_text = tick_labels(l.ay);
  // Horizontal: y title, y tick labels, frame, legend.
  double widest_y = 0, widest_legend = 0;
  for (const std::string& t : l.y_text) widest_y = std::max(widest_y, text_width(t, kTickFont));
  for (const PlotSeries& s : plot.series) widest_legend = std::max(widest_legend, text_width(s.label, kLegendFont));
  l.frame.x0 = 8 + kAxisFont + 12 + widest_y + 8;
  l.frame.x1 = kWidth - (plot.series.empty() ? 20 : 16 + l.swatch + 6 + widest_legend + 8);
  l.legend_x = l.frame.x1 + 16;
  l.ax = make_axis(plot.log_x, xs, static_cast<int>((l.frame.x1 - l.frame.x0) / kMinTickGapX) + 1);
  l.x_text = tick_labels(l.ax);
  return l;
}

void write_titles_and_axes(std::ostream& out, const SvgPlot& plot, const Layout& l) {
  const Box& f = l.frame;
  out << "<text x=\"" << kWidth / 2 << "\" y=\"" << l.title_y << "\" text-anchor=\"middle\" font-size=\"" << kTitleFont
      << "\" font-weight=\"bold\">" << xml_escape(plot.title) << "</text>\n";
  if (!plot.subtitle.empty()) {
    out << "<text x=\"" << kWidth / 2 << "\" y=\"" << l.subtitle_y << "\" text-anchor=\"middle\" font-size=\""
        << coord(fitting_font(plot.subtitle, kSubtitleFont, kWidth - 16)) << "\" fill=\"#444\">"
        << xml_escape(plot.subtitle) << "</text>\n";
  }
  for (std::size_t i = 0; i < l.ax.ticks.size(); ++i) {
    const std::string x = coord(l.px(l.ax.ticks[i]));
    out << "<line x1=\"" << x << "\" y1=\"" << coord(f.y0) << "\" x2=\"" << x << "\" y2=\"" << coord(f.y1 + 5)
        << "\" stroke=\"#ddd\"/><text class=\"tick-x\" x=\"" << x << "\" y=\"" << coord(f.y1 + 8 + kTickFont)
        << "\" text-anchor=\"middle\">" << l.x_text[i] << "</text>\n";
  }
  for (std::size_t i = 0; i < l.ay.ticks.size(); ++i) {
    const double y = l.py(l.ay.ticks[i]);
    out << "<line x1=\"" << coord(f.x0 - 5) << "\" y1=\"" << coord(y) << "\" x2=\"" << coord(f.x1) << "\" y2=\""
        << coord(y) << "\" stroke=\"#ddd\"/><text class=\"tick-y\" x=\"" << coord(f.x0 - 8) << "\" y=\""
        << coord(y + 0.35 * kTickFont) << "\" text-anchor=\"end\">" << l.y_text[i] << "</text>\n";
  }
  out << "<rect x=\"" << coord(f.x0) << "\" y=\"" << coord(f.y0) << "\" width=\"" << coord(f.x1 - f.x0)
      << "\" height=\"" << coord(f.y1 - f.y0) << "\" fill=\"none\" stroke=\"#333\"/>\n";
  out << "<text class=\"axis-title\" x=\"" << coord((f.x0 + f.x1) / 2) << "\" y=\"" << coord(kHeight - 10)
      << "\" text-anchor=\"middle\" font-size=\"" << coord(fitting_font(plot.x_label, kAxisFont, f.x1 - f.x0)) << "\">"
      << xml_escape(plot.x_label) << "</text>\n";
  out << "<text class=\"axis-title\" transform=\"translate(" << coord(8 + kAxisFont) << "," << coord((f.y0 + f.y1) / 2)
      << ") rotate(-90)\" text-anchor=\"middle\" font-size=\""
      << coord(fitting_font(plot.y_label, kAxisFont, f.y1 - f.y0)) << "\">" << xml_escape(plot.y_label) << "</text>\n";
}

std::string stroke_style(const std::string& color, LineStyle line) {
  std::string style = "stroke=\"" + color + "\" stroke-width=\"1.8\"";
  if (line != LineStyle::solid) style += std::string(" stroke-dasharray=\"") + dash_array(line) + "\"";
  return style;
}

struct PendingLabel {
  double x = 0, y = 0;  // the marker, px
  const std::string* text = nullptr;
  std::string color;
  bool end_of_series = false;
};

// What the curves cover, for the labels to avoid: markers strictly, lines if possible.
struct Covered {
  std::vector<Box> markers, lines;
};

// Curves and markers; returns the labels still to place.
std::vector<PendingLabel> write_series(std::ostream& out, const SvgPlot& plot, const Layout& l, Covered& covered) {
  std::vector<PendingLabel> pending;
  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    const PlotSeries& s = plot.series[i];
    const std::string color = series_color(s, i);
    std::string path, dots;
    std::optional<std::pair<double, double>> previous;  // the last accepted point, px
    std::vector<PendingLabel> labelled;
    for (std::size_t k = 0; k < s.points.size(); ++k) {
      const auto [x, y] = s.points[k];
      if (!accepted(l.ax.log, x) || !accepted(l.ay.log, y)) continue;
      const double X = l.px(x), Y = l.py(y), r = kMarkerRadius + 1;
      if (previous) add_segment_boxes(previous->first, previous->second, X, Y, covered.lines);
      previous = {X, Y};
      path += (path.empty() ? "M" : " L") + coord(X) + " " + coord(Y);
      dots += "<circle cx=\"" + coord(X) + "\" cy=\"" + coord(Y) + "\" r=\"" + coord(kMarkerRadius) + "\" fill=\"" +
              color + "\"/>\n";
      covered.markers.push_back({X - r, Y - r, X + r, Y + r});
      if (k < s.point_labels.size() && !s.point_labels[k].empty())
        labelled.push_back({X, Y, &s.point_labels[k], color, false});
    }
    if (!labelled.empty()) labelled.front().end_of_series = labelled.back().end_of_series = true;
    pending.insert(pending.end(), labelled.begin(), labelled.end());
    out << "<path d=\"" << path << "\" fill=\"none\" " << stroke_style(color, s.line) << "/>\n" << dots;
  }
  return pending;
}

void write_point_labels(std::ostream& out, std::vector<PendingLabel> pending, const Layout& l, const Covered& covered) {
  // Each series' first and last labels claim their spots before the ones between.
  std::stable_partition(pending.begin(), pending.end(), [](const PendingLabel& p) { return p.end_of_series; });
  std::vector<Box> taken = covered.markers;
  for (const PendingLabel& p : pending) {
    const double w = text_width(*p.text, kPointFont);
    const std::optional<Box> spot = place_label(label_spots(p.x, p.y, w, kPointFont), l.frame, taken, covered.lines);
    if (!spot) continue;
    taken.push_back(*spot);
    out << "<text class=\"point-label\" x=\"" << coord(spot->x0) << "\" y=\"" << coord(spot->y1 - 0.2 * kPointFont)
        << "\" font-size=\"" << kPointFont << "\" fill=\"" << p.color << "\">" << xml_escape(*p.text) << "</text>\n";
  }
}

void write_legend(std::ostream& out, const SvgPlot& plot, const Layout& l) {
  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    const PlotSeries& s = plot.series[i];
    const std::string color = series_color(s, i);
    const double x0 = l.legend_x, y = l.frame.y0 + 8 + 20.0 * static_cast<double>(i);
    out << "<line x1=\"" << coord(x0) << "\" y1=\"" << coord(y) << "\" x2=\"" << coord(x0 + l.swatch) << "\" y2=\""
        << coord(y) << "\" " << stroke_style(color, s.line) << "/><circle cx=\"" << coord(x0 + l.swatch / 2)
        << "\" cy=\"" << coord(y) << "\" r=\"" << coord(kMarkerRadius) << "\" fill=\"" << color
        << "\"/><text class=\"legend\" x=\"" << coord(x0 + l.swatch + 6) << "\" y=\"" << coord(y + 0.35 * kLegendFont)
        << "\" font-size=\"" << kLegendFont << "\">" << xml_escape(s.label) << "</text>\n";
  }
}

}  // namespace

void SvgPlot::write(std::ostream& out) const {
  const Layout layout = make_layout(*this);
  out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kWidth << "\" height=\"" << kHeight
      << "\" viewBox=\"0 0 " << kWidth << " " << kHeight
      << "\" font-family=\"DejaVu Sans, Arial, Helvetica, sans-serif\" font-size=\"" << kTickFont << "\">\n";
  out << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  write_titles_and_axes(out, *this, layout);
  Covered covered;
  std::vector<PendingLabel> pending = write_series(out, *this, layout, covered);
  write_point_labels(out, std::move(pending), layout, covered);  // on top of every curve
  write_legend(out, *this, layout);
  out << "</svg>\n";
}

bool spans_decades(const std::vector<double>& values, double ratio) {
  double lo = std::numeric_limits<double>::infinity(), hi = 0;
  for (const double v : values) {
    if (!(std::isfinite(v) && v > 0)) continue;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  return hi > 0 && hi / lo > ratio;
}

std::string short_number(double v, int significant) {
  // 1370 reads better than 1.37e3; beyond a million the exponent is shorter again.
  if (std::abs(v) >= std::pow(10.0, significant) && std::abs(v) < 1e6) return printf_number("%.*f", 0, v);
  return printf_number("%.*g", significant, v);
}

std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

}  // namespace visimp
