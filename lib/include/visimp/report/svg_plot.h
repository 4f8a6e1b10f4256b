// Minimal SVG line plots for reports: error against seconds (visibility study, QB vs VG
// curves). Axes may be logarithmic; points are drawn and joined per series.
#pragma once

#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace visimp {

struct PlotSeries {
  std::string label;
  std::vector<std::pair<double, double>> points;  ///< (x, y); non-finite or, on a log axis, non-positive points are skipped
  std::vector<std::string> point_labels;          ///< optional, one per point ("258 cameras")
};

struct SvgPlot {
  std::string title, x_label, y_label;
  bool log_x = false, log_y = false;
  std::vector<PlotSeries> series;

  void write(std::ostream& out) const;
};

/// `s` with <, >, & and " escaped, for SVG and HTML text and attributes.
std::string xml_escape(const std::string& s);

}  // namespace visimp
