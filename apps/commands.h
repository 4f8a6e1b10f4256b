// One function per `visimp` sub-command; each returns the process exit code and lets
// exceptions reach main, which maps them to the documented exit codes.
#pragma once

#include <string>
#include <vector>

namespace visimp::app {

using Args = std::vector<std::string>;

int run_simplify(const Args& args);
int run_info(const Args& args);
int run_convert(const Args& args);
int run_visibility(const Args& args);
int run_visibility_merge(const Args& args);
int run_orient(const Args& args);
int run_visibility_study(const Args& args);
int run_metro(const Args& args);
int run_imgerr(const Args& args);
int run_compare(const Args& args);
int run_patches(const Args& args);
int run_field(const Args& args);
int run_scene(const Args& args);
int run_cells(const Args& args);

}  // namespace visimp::app
