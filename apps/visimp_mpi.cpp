// visimp-mpi: `visimp visibility` with its cameras split over MPI processes
// (mpirun -np N visimp-mpi visibility IN OUT.ply [options]). Each process renders a contiguous
// slice; process 0 merges the tallies (integer sums: the output is byte-identical to one
// process's) and alone writes and reports. docs/mpi.md.
#include <mpi.h>

#include <cstdint>
#include <iostream>
#include <string>
#include <vector>

#include "cli.h"
#include "commands.h"
#include "visimp/core/errors.h"
#include "visimp/io/interrupt_cleanup.h"
#include "visimp/visibility/tally.h"

namespace visimp::app {
namespace {

constexpr const char* kUsage =
    "usage: mpirun -np N visimp-mpi visibility IN OUT.ply [options of 'visimp visibility']\n"
    "\n"
    "Computes V(t) as 'visimp visibility' does, the cameras split over the N processes. The output\n"
    "is byte-identical to one process's; process 0 writes it and the --json summary.\n"
    "'visimp-mpi visibility --help' lists the options.\n"
    "exit codes: 0 success, 1 bad input or I/O failure, 2 bad usage, 3 internal error\n";

class MpiSplit final : public CameraSplit {
 public:
  MpiSplit() {
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &ranks_);
  }
  int rank() const override { return rank_; }
  int ranks() const override { return ranks_; }

  VisibilityTally gather(const VisibilityTally& mine) override {
    const std::string bytes = mine.bytes();
    if (bytes.size() > static_cast<std::size_t>(INT32_MAX))
      throw UsageError("a tally of " + std::to_string(bytes.size()) + " bytes is too large for one MPI message");
    int size = static_cast<int>(bytes.size());
    std::vector<int> sizes(rank_ == 0 ? static_cast<std::size_t>(ranks_) : 0);
    MPI_Gather(&size, 1, MPI_INT, sizes.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
    std::vector<int> offsets(sizes.size(), 0);
    long long total = 0;
    for (std::size_t r = 0; r < sizes.size(); ++r) {
      if (total > INT32_MAX) throw UsageError("the tallies are too large for one MPI gather");
      offsets[r] = static_cast<int>(total);
      total += sizes[r];
    }
    std::string all(rank_ == 0 ? static_cast<std::size_t>(total) : 0, '\0');
    MPI_Gatherv(bytes.data(), size, MPI_CHAR, all.data(), sizes.data(), offsets.data(), MPI_CHAR, 0, MPI_COMM_WORLD);
    if (rank_ != 0) return {};
    VisibilityTally merged = mine;
    for (int r = 1; r < ranks_; ++r) {
      const auto i = static_cast<std::size_t>(r);
      merged.merge(VisibilityTally::parse(all.substr(static_cast<std::size_t>(offsets[i]), static_cast<std::size_t>(sizes[i])),
                                          "the tally of process " + std::to_string(r)));
    }
    return merged;
  }

 private:
  int rank_ = 0, ranks_ = 1;
};

}  // namespace
}  // namespace visimp::app

int main(int argc, char** argv) {
  using namespace visimp;
  using namespace visimp::app;
  MPI_Init(&argc, &argv);
  MpiSplit split;
  install_interrupt_cleanup();
  const std::string command = argc > 1 ? argv[1] : "";
  const Args args(argv + (argc > 1 ? 2 : 1), argv + argc);
  const int code = run_reporting_errors("visimp-mpi " + command, [&] {
    if (command == "--help" || command == "-h" || command.empty()) {
      if (split.rank() == 0) (command.empty() ? std::cerr : std::cout) << kUsage;
      return int(command.empty() ? kExitBadUsage : kExitSuccess);
    }
    if (command == "--version") {
      if (split.rank() == 0) std::cout << version_line() << "\n";
      return int(kExitSuccess);
    }
    if (command != "visibility") throw UsageError("only 'visibility' runs under MPI (see visimp-mpi --help)");
    // --help of the command: printed by process 0 only.
    if (split.rank() != 0)
      for (const std::string& a : args)
        if (a == "--help") return int(kExitSuccess);
    return run_visibility(args, &split);
  });
  // A process that failed alone would leave the others waiting in the gather: stop them all.
  if (code != kExitSuccess && split.ranks() > 1) MPI_Abort(MPI_COMM_WORLD, code);
  MPI_Finalize();
  return code;
}
