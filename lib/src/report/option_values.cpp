#include "visimp/report/option_values.h"

#include <algorithm>
#include <cstdint>
#include <string>

namespace visimp {

void write_option_values(JsonWriter& json, const std::vector<OptionSpec>& specs) {
  json.begin_object();
  for (const OptionSpec& spec : specs) {
    if (spec.flag == "--threads") continue;  // never changes a result (same bytes for any count)
    std::string key = spec.flag.substr(spec.flag.find_first_not_of('-'));
    std::replace(key.begin(), key.end(), '-', '_');
    json.key(key);
    switch (spec.kind) {
      case OptionKind::count:
        json.value(static_cast<std::uint64_t>(*static_cast<const std::size_t*>(spec.target)));
        break;
      case OptionKind::integer:
        json.value(*static_cast<const int*>(spec.target));
        break;
      case OptionKind::number:
        json.value(*static_cast<const double*>(spec.target));
        break;
      case OptionKind::text:
        json.value(*static_cast<const std::string*>(spec.target));
        break;
      case OptionKind::choice:
        json.value(spec.default_text);
        break;
      case OptionKind::toggle:
        json.value(*static_cast<const bool*>(spec.target));
        break;
      case OptionKind::negated_toggle:
        json.value(!*static_cast<const bool*>(spec.target));
        break;
    }
  }
  json.end_object();
}

}  // namespace visimp
