// One function per `visimp` sub-command; each returns the process exit code and lets
// exceptions reach main, which maps them to the documented exit codes.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace visimp {
struct VisibilityTally;
}

namespace visimp::app {

using Args = std::vector<std::string>;

int run_simplify(const Args& args);
int run_info(const Args& args);
int run_convert(const Args& args);
/// How `visibility` shares its cameras between processes (visimp-mpi): this process renders
/// its slice, gather() hands every slice's tally to process 0, which alone writes and reports.
class CameraSplit {
 public:
  virtual ~CameraSplit() = default;
  virtual int rank() const = 0;
  virtual int ranks() const = 0;
  /// Every process calls this with its slice; process 0 gets them all merged, the others an
  /// empty tally.
  virtual VisibilityTally gather(const VisibilityTally& mine) = 0;
};

/// Cameras [first, last) split into `ranks` contiguous slices; the slice of `rank`.
std::pair<std::size_t, std::size_t> camera_slice(std::size_t first, std::size_t last, int rank, int ranks);

int run_visibility(const Args& args, CameraSplit* split = nullptr);
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
