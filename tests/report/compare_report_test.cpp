// report.html and the plots of `visimp compare` on a CompareResult written by hand, so every
// number the page quotes is known: VG collapses a hidden part (Hausdorff and RMS 40× and
// 500× QB's) and wins on the image and the visible error, the case the page must explain.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <regex>
#include <string>

#include "temp_dir.h"
#include "test_meshes.h"
#include "visimp/compare/compare.h"

namespace visimp {
namespace {

// Two levels, 200 and 100 faces, on a 320-face sphere of diagonal 2 (relative = absolute / 2).
CompareResult hidden_part_collapsed(const Mesh& input) {
  CompareResult r;
  r.faces_in = input.num_faces();
  r.diagonal = 2;
  r.visibility.face.assign(input.num_faces(), 1.0f);
  r.visibility.mesh = 0.75;
  r.visibility.stats.hidden_area_fraction = 0.25;
  r.targets = {200, 100};
  for (std::size_t i = 0; i < 2; ++i) {
    const double k = double(i + 1);  // the coarser level has twice QB's errors
    CompareLevel q, v;
    q.target = v.target = q.faces = v.faces = r.targets[i];
    q.mesh = v.mesh = input;
    for (CompareLevel* l : {&q, &v}) {
      l->image.views = 20;
      l->image.resolution = 256;
      l->image.supersample = 4;
    }
    q.image.rms = 1000 * k;
    v.image.rms = 900 * k;  // VG 10% ahead at both levels
    q.distance.hausdorff = 0.002 * k;
    v.distance.hausdorff = 0.08;  // the hidden part gone: 40× and 20× QB's
    q.distance.rms = 2e-5 * k;
    v.distance.rms = 0.01;
    q.distance.visible.rms = 3e-5 * k;
    v.distance.visible.rms = 1e-5 * k;  // below QB's: what is seen is closer
    q.distance.visible.mean = 2e-5 * k;
    v.distance.visible.mean = 1e-5 * k;
    q.distance.visible.max = v.distance.visible.max = 1e-4;
    r.qb.push_back(q);
    r.vg.push_back(v);
  }
  r.less_image_error_percent_per_level = {10, 10};
  r.less_image_error_percent = 10;
  return r;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<std::string> tick_labels(const std::string& svg, const std::string& axis) {
  std::vector<std::string> out;
  const std::regex tick("<text class=\"tick-" + axis + "\"[^>]*>([^<]*)</text>");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), tick); it != std::sregex_iterator(); ++it)
    out.push_back((*it)[1]);
  return out;
}

TEST(CompareReport, PageExplainsWhyHausdorffRisesWhileTheImageErrorFalls) {
  const Mesh sphere = test::icosphere(2);
  const test::TempDir temp("compare_report_page");
  write_compare_report(hidden_part_collapsed(sphere), sphere, "sphere", temp.path());
  const std::string page = read_text(temp.path() + "/report.html");
  for (const char* quote : {
           "25.0% of this input's area is never seen (V = 0)",
           "VG's Hausdorff distance is above QB's at 2 of 2 levels (up to 40× QB's)",
           "its RMS at 2 of 2 levels, while its image error is below QB's at 2 of 2 levels",
           "<b>visible error</b>",
           "VG's visible RMS is below QB's at 2 of 2 levels.",
           // The scale of "image RMS", in this run's numbers (image_error.h, eq. 5.11).
           "over 20 views of 256² px, I in grey levels 0..255, 4×4 samples a pixel",
           "divide by 1145",  // sqrt(20) · 256 = 1144.9
           // Summary row of the 200-face level: image RMS, VG's lead, visible RMS / diag, VG lower in bold.
           "<td>1000</td><td class=\"lower\">900</td><td>+10.0</td><td>1.5e-5</td><td class=\"lower\">5e-6</td>",
       }) {
    EXPECT_NE(page.find(quote), std::string::npos) << quote;
  }
  // Every level VG wins on visible RMS: no sentence about it moving seen surface further.
  EXPECT_EQ(page.find("moved seen surface"), std::string::npos);
}

TEST(CompareReport, GeometricErrorsSpanningDecadesGetALogAxisAndTheImageErrorALinearOne) {
  const Mesh sphere = test::icosphere(2);
  const test::TempDir temp("compare_report_axes");
  write_compare_report(hidden_part_collapsed(sphere), sphere, "sphere", temp.path());
  // 5e-6 (VG's visible RMS at 200 faces) … 0.04 (its Hausdorff): almost four decades.
  const std::vector<std::string> geometric = tick_labels(read_text(temp.path() + "/geometric_error_vs_faces.svg"), "y");
  ASSERT_GE(geometric.size(), 3u);
  for (const std::string& t : geometric) EXPECT_TRUE(std::regex_match(t, std::regex("1e-[0-9]+"))) << t;
  // 900 … 2000: a factor 2.2, so linear; padded by 4% (856 … 2044), 1188 / 7 intervals → step
  // 200, the frame widened to whole steps. Zero is not forced in: the padding does not reach it.
  EXPECT_EQ(tick_labels(read_text(temp.path() + "/image_error_vs_faces.svg"), "y"),
            (std::vector<std::string>{"800", "1000", "1200", "1400", "1600", "1800", "2000", "2200"}));
  // The faces are always on a log axis; 87 … 230 (padded ×1.15) holds only two 1-2-5 values,
  // so the ticks step linearly by 50 (143 / 4 → 50).
  const std::vector<std::string> faces = tick_labels(read_text(temp.path() + "/image_error_vs_faces.svg"), "x");
  EXPECT_EQ(faces, (std::vector<std::string>{"100", "150", "200"}));
}

}  // namespace
}  // namespace visimp
