// The options a result was made with, as one JSON object: what the apps' --json summaries and
// compare's results.json record, so that a pipeline can tell two runs apart or redo one.
#pragma once

#include <vector>

#include "visimp/core/option_table.h"
#include "visimp/report/json.h"

namespace visimp {

/// Writes the values `specs`' fields hold now as one JSON object keyed by flag
/// ("--max-normal-change" -> "max_normal_change", "--no-refine" -> "no_refine"): numbers as
/// numbers (inf: null), names and text as strings, a switch as whether its flag is in effect.
/// --threads is left out: it changes no result. `specs` must be made after the fields were set
/// (describe_options of the structs as run): a choice's name is taken when its spec is made.
void write_option_values(JsonWriter& json, const std::vector<OptionSpec>& specs);

}  // namespace visimp
