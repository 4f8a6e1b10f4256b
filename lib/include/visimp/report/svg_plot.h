// Minimal SVG line plots for reports: error against seconds (visibility study, QB vs VG
// curves). Axes may be logarithmic; points are drawn and joined per series.
//
// Layout contract (what a reader of the picture can rely on): tick values are "nice" (1, 2, 5
// × 10^k steps on a linear axis; 1-2-5, 1-3 or whole decades on a log axis), at most one
// every ~70 px across and ~40 px up; margins are sized from the widest tick label, so an axis
// title never covers one; a point label is drawn only where its box, estimated from the font
// size, overlaps no other label and no marker (the first and last of each series are placed
// first), otherwise it is dropped.
// New members carry default initializers so that callers initialising the older ones by
// position ({label, points, labels}) stay free of -Wmissing-field-initializers.
#pragma once

#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace visimp {

enum class LineStyle { solid, dashed, dotted };

struct PlotSeries {
  std::string label;
  /// (x, y); non-finite points and, on a log axis, non-positive ones are skipped.
  std::vector<std::pair<double, double>> points;
  /// Optional, one per point ("258 cameras"); a label that would collide is dropped.
  std::vector<std::string> point_labels;
  std::string color = {};  ///< CSS colour; empty: the next of the plot's palette
  LineStyle line = LineStyle::solid;
};

struct SvgPlot {
  std::string title, x_label, y_label;
  bool log_x = false, log_y = false;
  std::vector<PlotSeries> series;
  /// Optional second line under the title (units, definitions); one line of ~90 characters.
  std::string subtitle = {};

  void write(std::ostream& out) const;
};

/// True when the positive finite `values` span more than a factor `ratio` (max / min): a
/// linear axis would flatten the small ones against zero. Non-positive values are ignored.
bool spans_decades(const std::vector<double>& values, double ratio = 20);

/// `v` with `significant` digits, exponent without padding ("6.63e-6", "0.0406"); whole
/// numbers below a million in full ("1370", not "1.37e3").
std::string short_number(double v, int significant = 3);

/// `s` with <, >, & and " escaped, for SVG and HTML text and attributes.
std::string xml_escape(const std::string& s);

}  // namespace visimp
