// The apps' shared command-line machinery: a parser built from OptionSpecs (so --help text
// and defaults come from the library's options structs), mesh in/out helpers honouring "-"
// and --format, and a progress bar shown only when stderr is a terminal.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "visimp/core/errors.h"
#include "visimp/core/mesh.h"
#include "visimp/core/option_table.h"
#include "visimp/io/mesh_io.h"
#include "visimp/render/renderer.h"
#include "visimp/simplify/simplify.h"

namespace visimp::app {

// The exit codes of every visimp app (README and --help document them).
enum ExitCode : int {
  kExitSuccess = 0,
  kExitBadInput = 1,  ///< a file could not be read, parsed or written, a mesh is invalid, or a backend cannot run
  kExitBadUsage = 2,  ///< unknown flag, missing or malformed argument, option out of range
  kExitInternal = 3,  ///< anything else: a bug in visimp
};

/// Runs `body` and maps what it throws to one "PROGRAM: error: ..." line on stderr and the
/// exit code of its kind (every app's main goes through this).
int run_reporting_errors(const std::string& program, const std::function<int()>& body);

class ArgParser {
 public:
  /// usage: "visimp simplify IN OUT (--target N | --ratio R | --max-error E) [options]".
  ArgParser(std::string usage, std::string description, std::size_t positionals)
      : ArgParser(std::move(usage), std::move(description), positionals, positionals) {}
  /// Accepts between min_positionals and max_positionals file arguments.
  ArgParser(std::string usage, std::string description, std::size_t min_positionals, std::size_t max_positionals);
  void add(OptionSpec spec) { specs_.push_back(std::move(spec)); }
  void add(std::vector<OptionSpec> specs);
  /// The same, leaving out the flags that do not apply to this command (its --help must
  /// list only what it uses).
  void add(std::vector<OptionSpec> specs, const std::vector<std::string>& except);
  /// The positional OUT at `index` may also be given as -o OUT (the same everywhere).
  void allow_output_flag(std::size_t index);
  /// Whether the flag appeared on the command line (to tell "--ratio 0" from no --ratio).
  bool given(const std::string& flag) const;
  /// Flag of each bound field of the last parse, kept past the parser's life: main reports
  /// errors after the command's locals are gone. (Addresses as integers, only compared.)
  static inline std::vector<std::pair<std::uintptr_t, std::string>> bound_flags_;
  /// Parses args (after the command name). Returns false when --help was printed.
  /// Throws UsageError for unknown flags, missing values or a wrong number of positionals.
  bool parse(const std::vector<std::string>& args);
  const std::vector<std::string>& positionals() const { return positionals_; }
  std::string help() const;

 private:
  std::string usage_, description_;
  std::size_t min_positionals_, max_positionals_;
  std::vector<OptionSpec> specs_;
  std::vector<std::string> positionals_;
  std::vector<std::string> given_;
  std::optional<std::size_t> output_index_;  // allow_output_flag
  std::string output_flag_value_;
};

/// The library's complaint about a field in the terms of the last command line parsed:
/// "--ratio must be ..." for a field a flag was bound to, the library's own words otherwise.
std::string describe_option_error(const OptionError& e);

/// Throws UsageError "FLAG must be in 16..8192" unless `pixels` is a size every renderer takes.
void check_pixels(std::size_t pixels, const std::string& flag);
/// The size of the pictures the apps write (--png, error and patch maps).
inline constexpr int kPictureSize = 800;

/// "visimp 0.1.0".
std::string version_line();

/// Options every command that reads or writes meshes shares.
struct StreamOptions {
  std::string format;         // format of "-" for input and output
  std::string input_format;   // overrides format for the input
  std::string output_format;  // overrides format for the output
  bool ascii = false;         // PLY/STL: write ascii instead of binary
  bool in_place = false;      // allow OUT to be the same file as IN
  bool json = false;          // machine-readable summary
  /// Set by read_input: the format the (last) input was read as, and whether its content
  /// decided it. "-" as OUT without --format is written in that format.
  std::optional<FormatChoice> input_choice;
};
std::vector<OptionSpec> describe_options(StreamOptions& o, bool has_output);

Mesh read_input(const std::string& path, StreamOptions& o);
/// Throws InvalidMeshError (exit 1) naming `path` when the mesh has no faces: nothing to
/// `what` ("simplify", "measure", "compare").
void require_faces(const Mesh& mesh, const std::string& path, const std::string& what);
/// For --json: the input's format ("" before read_input) and whether its content decided it.
std::string input_format_name(const StreamOptions& o);
bool input_format_detected(const StreamOptions& o);

/// "X,Y,Z" → a finite point; throws UsageError naming `what`.
Vec3 parse_point(const std::string& text, const std::string& what);
/// "50000,20000,5000" → counts; throws UsageError naming `what`.
std::vector<std::size_t> parse_count_list(const std::string& text, const std::string& what);
/// Refuses to overwrite `input` unless --in-place; writes atomically.
/// `source_face` (PLY): also write which input face each face came from.
void write_output(const Mesh& mesh, const std::string& path, const std::string& input, const StreamOptions& o,
                  const std::vector<std::uint32_t>* source_face = nullptr);

class ProgressBar : public SimplifyObserver, public RenderObserver {
 public:
  explicit ProgressBar(std::string label);
  ~ProgressBar() override;
  void on_progress(double fraction) override;
  void on_render_progress(double fraction) override { on_progress(fraction); }

 private:
  std::string label_;
  bool enabled_;
  int last_percent_ = -1;
};

}  // namespace visimp::app
