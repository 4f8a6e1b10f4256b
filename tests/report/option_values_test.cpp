// write_option_values: each kind of option as its JSON type, keyed by its flag.
#include <gtest/gtest.h>

#include <limits>
#include <sstream>
#include <string>

#include "visimp/report/option_values.h"

namespace visimp {
namespace {

enum class Shade { light, dark };

TEST(OptionValues, WritesEachKindAsItsJsonTypeKeyedByItsFlag) {
  std::size_t samples = 100;
  int pixels = 64;
  double ratio = 0.25, limit = std::numeric_limits<double>::infinity();
  std::string cameras = "k3";
  Shade shade = Shade::light;
  bool folds_off = false, refine = true, fractional = false;
  std::size_t threads = 2;
  auto specs = [&] {  // made after the fields are set, as the apps do
    return std::vector<OptionSpec>{
        option_spec("--metro-samples", "N", samples, ""),
        option_spec("--image-resolution", "R", pixels, ""),
        option_spec("--ratio", "R", ratio, ""),
        option_spec("--max-error", "E", limit, ""),
        option_spec("--cameras", "SET", cameras, ""),
        choice_spec("--shade", "S", shade, {{"light", Shade::light}, {"dark", Shade::dark}}, ""),
        switch_spec("--no-folds", folds_off, ""),
        negated_switch_spec("--no-refine", refine, ""),
        switch_spec("--fractional", fractional, ""),
        option_spec("--threads", "N", threads, "")};
  };
  for (OptionSpec& s : specs()) {  // parse as a command line would
    if (s.flag == "--ratio") s.set("0.5");
    if (s.flag == "--shade") s.set("dark");
    if (s.flag == "--no-folds" || s.flag == "--no-refine") s.set("");
  }
  std::ostringstream out;
  JsonWriter json(out);
  write_option_values(json, specs());
  const std::string text = out.str();
  for (const char* field :
       {"\"metro_samples\": 100", "\"image_resolution\": 64", "\"ratio\": 0.5", "\"max_error\": null",
        "\"cameras\": \"k3\"", "\"shade\": \"dark\"", "\"no_folds\": true", "\"no_refine\": true", "\"fractional\": false"})
    EXPECT_NE(text.find(field), std::string::npos) << field << "\n" << text;
  EXPECT_EQ(text.find("threads"), std::string::npos) << "the thread count changes no result";
}

}  // namespace
}  // namespace visimp
