// The plotter's layout promises (svg_plot.h), read back from the SVG it writes: nice tick
// values, log axes where asked, margins that keep the y title off the tick labels, and point
// labels that never overlap.
#include "visimp/report/svg_plot.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace visimp {
namespace {

struct SvgText {
  double x = 0, y = 0, font = 0;
  std::string text;
};

std::string render(const SvgPlot& plot) {
  std::ostringstream s;
  plot.write(s);
  return s.str();
}

// Every <text class="CLASS" x=".." y=".." ...>TEXT</text> of the SVG, in order.
std::vector<SvgText> texts(const std::string& svg, const std::string& cls) {
  std::vector<SvgText> out;
  const std::regex element("<text class=\"" + cls + "\" x=\"([-0-9.]+)\" y=\"([-0-9.]+)\"([^>]*)>([^<]*)</text>");
  const std::regex font_size("font-size=\"([0-9.]+)\"");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), element); it != std::sregex_iterator(); ++it) {
    SvgText t{std::stod((*it)[1]), std::stod((*it)[2]), 13, (*it)[4]};
    const std::string rest = (*it)[3];
    std::smatch size;
    if (std::regex_search(rest, size, font_size)) t.font = std::stod(size[1]);
    out.push_back(t);
  }
  return out;
}

std::vector<std::string> labels(const std::vector<SvgText>& ts) {
  std::vector<std::string> out;
  for (const SvgText& t : ts) out.push_back(t.text);
  return out;
}

SvgPlot one_series(std::vector<std::pair<double, double>> points, bool log_x, bool log_y) {
  SvgPlot p;
  p.title = "t";
  p.x_label = "x";
  p.y_label = "y";
  p.log_x = log_x;
  p.log_y = log_y;
  p.series.push_back({"s", std::move(points), {}});
  return p;
}

TEST(SvgPlot, LogAxisOverFourDecadesIsLabelledAtEachPowerOfTen) {
  // 1-2-5 per decade would need 13 ticks on a ~340 px axis (at most one per 40 px): too many,
  // so whole decades; the range is padded, not widened, so 1e-6 … 1e-2 are all of them.
  const std::string svg = render(one_series({{1, 1e-6}, {2, 1e-4}, {3, 1e-2}}, false, true));
  EXPECT_EQ(labels(texts(svg, "tick-y")), (std::vector<std::string>{"1e-6", "1e-5", "1e-4", "1e-3", "1e-2"}));
}

TEST(SvgPlot, LogAxisOverOneDecadeUsesOneTwoFive) {
  // The faces of visimp compare's default levels on the ESP module: 326 … 4892, padded ×1.15.
  const std::string svg = render(one_series({{326, 1}, {1264, 2}, {4892, 3}}, true, false));
  EXPECT_EQ(labels(texts(svg, "tick-x")), (std::vector<std::string>{"500", "1000", "2000", "5000"}));
}

TEST(SvgPlot, LinearAxisStepsAreOneTwoFiveWithOneFormat) {
  // 0 … 1 padded by 4% is 1.04; 1.04 / 7 intervals → step 0.2, the frame ends on the tick 1.2.
  const std::string svg = render(one_series({{0, 0}, {1, 0.5}, {2, 1}}, false, false));
  EXPECT_EQ(labels(texts(svg, "tick-y")), (std::vector<std::string>{"0.0", "0.2", "0.4", "0.6", "0.8", "1.0", "1.2"}));
}

TEST(SvgPlot, YTitleKeepsClearOfTheWidestTickLabel) {
  // Labels such as "0.000125" are the widest a linear axis writes in plain decimals.
  const std::string svg = render(one_series({{0, 1e-4}, {1, 9e-4}}, false, false));
  const std::smatch title = [&] {
    std::smatch m;
    EXPECT_TRUE(std::regex_search(svg, m, std::regex("class=\"axis-title\" transform=\"translate\\(([0-9.]+),")));
    return m;
  }();
  const double title_right = std::stod(title[1]) + 0.2 * 14;  // rotated: the descent points right
  const std::vector<SvgText> ticks = texts(svg, "tick-y");
  ASSERT_GE(ticks.size(), 2u);
  for (const SvgText& t : ticks) {
    // Right-aligned at x; 0.62 em a character is the plotter's own (generous) estimate.
    EXPECT_LT(title_right, t.x - 0.62 * t.font * static_cast<double>(t.text.size())) << t.text;
  }
}

TEST(SvgPlot, PointLabelsNeverOverlapAndTheEndsOfASeriesAreKept) {
  // 120 points 4 px apart on a diagonal: room for a label at only some of them. The ends are
  // offset from the frame (x, y from 10), so they have room and must get theirs.
  SvgPlot p = one_series({}, false, false);
  const int n = 120;
  for (int i = 0; i < n; ++i) {
    p.series[0].points.emplace_back(i + 10, i + 10);
    p.series[0].point_labels.push_back(i == 0 ? "first" : i == n - 1 ? "last" : std::to_string(1000 + i));
  }
  const std::vector<SvgText> placed = texts(render(p), "point-label");
  EXPECT_LT(placed.size(), static_cast<std::size_t>(n));  // some had to go
  const std::vector<std::string> names = labels(placed);
  EXPECT_NE(std::find(names.begin(), names.end(), "first"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "last"), names.end());
  for (std::size_t a = 0; a < placed.size(); ++a) {
    for (std::size_t b = a + 1; b < placed.size(); ++b) {
      const SvgText &u = placed[a], &v = placed[b];
      const double uw = 0.62 * u.font * static_cast<double>(u.text.size()),
                   vw = 0.62 * v.font * static_cast<double>(v.text.size());
      const bool apart = u.x + uw <= v.x || v.x + vw <= u.x || u.y + 0.2 * u.font <= v.y - 0.8 * v.font ||
                         v.y + 0.2 * v.font <= u.y - 0.8 * u.font;
      EXPECT_TRUE(apart) << u.text << " and " << v.text;
    }
  }
}

// Found by the visibility study's plot: a log range holding no 1-2-5 value at all (its
// seconds between 5.2 and 7.7 ms) looped until a counter overflowed (SIGFPE).
TEST(SvgPlot, LogRangeBetweenTwoNiceValuesGetsTicks) {
  SvgPlot plot;
  plot.log_x = plot.log_y = true;
  PlotSeries s;
  s.points = {{0.0052, 0.042}, {0.0077, 0.021}};
  plot.series.push_back(s);
  std::ostringstream out;
  plot.write(out);
  EXPECT_NE(out.str().find("</svg>"), std::string::npos);
  EXPECT_GE(texts(out.str(), "tick-x").size(), 2u);
}

TEST(SvgPlot, NonPositivePointsAreLeftOffALogAxis) {
  const std::string svg = render(one_series({{1, 0.0}, {2, 1e-3}, {3, 1e-1}}, false, true));
  const std::regex circle("<circle ");
  // Two markers in the plot and one in the legend.
  EXPECT_EQ(std::distance(std::sregex_iterator(svg.begin(), svg.end(), circle), std::sregex_iterator()), 3);
}

TEST(SvgPlot, TextIsEscaped) {
  SvgPlot p = one_series({{1, 1}}, false, false);
  p.title = "a < b & \"c\"";
  EXPECT_NE(render(p).find("a &lt; b &amp; &quot;c&quot;"), std::string::npos);
}

TEST(SpansDecades, ComparesMaxOverMinOfThePositiveValues) {
  EXPECT_FALSE(spans_decades({1, 10}));
  EXPECT_FALSE(spans_decades({1, 20}));  // exactly the factor: not more
  EXPECT_TRUE(spans_decades({1, 21}));
  EXPECT_TRUE(spans_decades({0, -5, 1, 30}));  // 0 and -5 cannot go on a log axis anyway
  EXPECT_FALSE(spans_decades({}));
  EXPECT_FALSE(spans_decades({0, 0}));
}

TEST(ShortNumber, SignificantDigitsWithoutPaddedExponents) {
  EXPECT_EQ(short_number(6.634e-6), "6.63e-6");
  EXPECT_EQ(short_number(0.0406414), "0.0406");
  EXPECT_EQ(short_number(1369.9), "1370");  // whole numbers under a million in full
  EXPECT_EQ(short_number(873.28), "873");
  EXPECT_EQ(short_number(2.5e7), "2.5e7");
  EXPECT_EQ(short_number(2e-5, 2), "2e-5");
}

}  // namespace
}  // namespace visimp
