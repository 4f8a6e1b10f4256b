#include "cli.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <new>
#include <sstream>

#include "visimp/core/errors.h"

namespace visimp::app {

int run_reporting_errors(const std::string& program, const std::function<int()>& body) {
  try {
    return body();
  } catch (const OptionError& e) {
    std::cerr << program << ": error: " << describe_option_error(e) << "\n";
    return kExitBadUsage;
  } catch (const BackendError& e) {
    std::cerr << program << ": error: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const UsageError& e) {
    std::cerr << program << ": error: " << e.what() << "\n";
    return kExitBadUsage;
  } catch (const IoError& e) {
    std::cerr << program << ": error: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const InvalidMeshError& e) {
    std::cerr << program << ": error: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::bad_alloc&) {
    std::cerr << program << ": error: out of memory\n";
    return kExitInternal;
  } catch (const std::exception& e) {
    std::cerr << program << ": internal error: " << e.what() << "\n";
    return kExitInternal;
  }
}

ArgParser::ArgParser(std::string usage, std::string description, std::size_t min_positionals,
                     std::size_t max_positionals)
    : usage_(std::move(usage)),
      description_(std::move(description)),
      min_positionals_(min_positionals),
      max_positionals_(max_positionals) {}

void ArgParser::add(std::vector<OptionSpec> specs) {
  for (auto& s : specs) specs_.push_back(std::move(s));
}

void ArgParser::add(std::vector<OptionSpec> specs, const std::vector<std::string>& except) {
  for (auto& s : specs) {
    if (std::find(except.begin(), except.end(), s.flag) == except.end()) specs_.push_back(std::move(s));
  }
}

void ArgParser::allow_output_flag(std::size_t index) {
  output_index_ = index;
  specs_.push_back(option_spec("-o", "OUT", output_flag_value_, "the output file (the same as giving OUT)"));
}

bool ArgParser::given(const std::string& flag) const {
  return std::find(given_.begin(), given_.end(), flag) != given_.end();
}

void check_pixels(std::size_t pixels, const std::string& flag) {
  if (pixels < static_cast<std::size_t>(kMinResolution) || pixels > static_cast<std::size_t>(kMaxResolution)) {
    throw UsageError(flag + " must be in " + std::to_string(kMinResolution) + ".." + std::to_string(kMaxResolution));
  }
}

std::string version_line() { return std::string("visimp ") + VISIMP_VERSION; }

std::string describe_option_error(const OptionError& e) {
  const auto field = reinterpret_cast<std::uintptr_t>(e.field());
  for (const auto& [target, flag] : ArgParser::bound_flags_) {
    if (field != 0 && target == field) return flag + " " + e.problem();
  }
  return e.what();
}

bool ArgParser::parse(const std::vector<std::string>& args) {
  bound_flags_.clear();
  for (const OptionSpec& spec : specs_)
    bound_flags_.emplace_back(reinterpret_cast<std::uintptr_t>(spec.target), spec.flag);
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--help" || a == "-h") {
      std::cout << help();
      return false;
    }
    if (a == "--version") {
      std::cout << version_line() << "\n";
      return false;
    }
    const bool long_flag = a.size() > 2 && a.compare(0, 2, "--") == 0;
    const bool short_flag = a.size() == 2 && a[0] == '-' && a[1] != '-';  // "-o"; "-" alone is stdin/stdout
    if (long_flag || short_flag) {
      const std::size_t eq = a.find('=');
      const std::string flag = a.substr(0, eq);
      const OptionSpec* spec = nullptr;
      for (const auto& s : specs_)
        if (s.flag == flag) spec = &s;
      if (!spec) throw UsageError("unknown option " + flag + " (see --help)");
      given_.push_back(flag);
      if (spec->value_name.empty()) {
        if (eq != std::string::npos) throw UsageError(flag + " takes no value");
        spec->set("");
      } else if (eq != std::string::npos) {
        spec->set(a.substr(eq + 1));
      } else if (!spec->implicit_value.empty()) {
        const bool next_is_number = i + 1 < args.size() && !args[i + 1].empty() &&
                                    (std::isdigit(static_cast<unsigned char>(args[i + 1][0])) || args[i + 1][0] == '.');
        spec->set(next_is_number ? std::string_view(args[++i]) : std::string_view(spec->implicit_value));
      } else {
        if (i + 1 >= args.size()) throw UsageError(flag + " needs a value " + spec->value_name);
        spec->set(args[++i]);
      }
    } else {
      positionals_.push_back(a);  // includes "-" (stdin/stdout)
    }
  }
  if (output_index_ && given("-o")) {
    if (positionals_.size() != *output_index_) {
      throw UsageError("give OUT either as an argument or with -o, once (usage: " + usage_ + ")");
    }
    positionals_.push_back(output_flag_value_);
  }
  if (positionals_.size() < min_positionals_ || positionals_.size() > max_positionals_) {
    const std::string expected =
        max_positionals_ == std::numeric_limits<std::size_t>::max()
            ? "at least " + std::to_string(min_positionals_)
            : std::to_string(min_positionals_) +
                  (max_positionals_ != min_positionals_ ? ".." + std::to_string(max_positionals_) : "");
    throw UsageError("expected " + expected + " file argument(s), got " + std::to_string(positionals_.size()) +
                     " (usage: " + usage_ + ")");
  }
  return true;
}

std::string ArgParser::help() const {
  std::ostringstream s;
  s << "usage: " << usage_ << "\n\n" << description_ << "\n\noptions:\n";
  for (const auto& spec : specs_) {
    std::string value = spec.value_name;
    if (!value.empty() && !spec.implicit_value.empty()) value = "[" + value + "]";
    std::string left = "  " + spec.flag + (value.empty() ? "" : " " + value);
    if (left.size() < 28)
      left.resize(28, ' ');
    else
      left += "  ";
    s << left << spec.help;
    if (!spec.value_name.empty() && !spec.default_text.empty()) s << " [default: " << spec.default_text << "]";
    s << "\n";
  }
  s << "  --help                      show this text\n"
       "  --version                   print visimp's version\n\n"
       "\"-\" as a file means standard input/output (read: the content tells the format; written: as read, or "
       "--format).\n"
       "exit codes: 0 success, 1 bad input or I/O failure, 2 bad usage, 3 internal error\n";
  return s.str();
}

std::vector<OptionSpec> describe_options(StreamOptions& o, bool has_output) {
  std::vector<OptionSpec> specs = {
      option_spec("--format", "F", o.format, "format of '-' streams: ply, obj, off or stl"),
      option_spec("--input-format", "F", o.input_format, "input format, overriding the extension"),
      switch_spec("--json", o.json, "print a machine-readable JSON summary"),
  };
  if (has_output) {
    specs.push_back(option_spec("--output-format", "F", o.output_format, "output format, overriding the extension"));
    specs.push_back(switch_spec("--ascii", o.ascii, "write PLY/STL as ASCII instead of binary"));
    specs.push_back(switch_spec("--in-place", o.in_place, "allow OUT to be the input file itself"));
  }
  return specs;
}

namespace {
std::optional<Format> chosen_format(const std::string& specific, const std::string& general) {
  const std::string& name = specific.empty() ? general : specific;
  if (name.empty()) return std::nullopt;
  const auto f = parse_format(name);
  if (!f) throw UsageError("unknown format '" + name + "' (use ply, obj, off or stl; gltf, glb, 3mf, dae, fbx or x3d to read)");
  return f;
}
}  // namespace

std::vector<std::size_t> parse_count_list(const std::string& text, const std::string& what) {
  std::vector<std::size_t> counts;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    counts.push_back(parse_count(std::string_view(text).substr(start, comma - start), what));
    start = comma + 1;
  }
  return counts;
}

Mesh read_input(const std::string& path, StreamOptions& o) {
  FormatChoice choice;
  Mesh mesh = read_mesh(path, chosen_format(o.input_format, o.format), &choice);
  o.input_choice = choice;
  return mesh;
}

void require_faces(const Mesh& mesh, const std::string& path, const std::string& what) {
  if (mesh.num_faces() > 0) return;
  throw InvalidMeshError((path == "-" ? std::string("<stdin>") : path) + ": no faces to " + what + " (" +
                         std::to_string(mesh.num_vertices()) + " vertices, 0 faces)");
}

std::string input_format_name(const StreamOptions& o) {
  return o.input_choice ? format_name(o.input_choice->format) : "";
}
bool input_format_detected(const StreamOptions& o) { return o.input_choice && o.input_choice->detected; }

void write_output(const Mesh& mesh, const std::string& path, const std::string& input, const StreamOptions& o,
                  const std::vector<std::uint32_t>* source_face) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (path != "-" && input != "-" && !o.in_place && fs::exists(path, ec) && fs::equivalent(path, input, ec))
    throw UsageError(path + ": output would overwrite the input (use --in-place to allow it)");
  WriteOptions w;
  w.binary = !o.ascii;
  w.source_face = source_face;
  std::optional<Format> format = chosen_format(o.output_format, o.format);
  // stdout: as the input came, or PLY when that format is read-only (a glb from stdin).
  if (!format && path == "-" && o.input_choice) format = is_writable(o.input_choice->format) ? o.input_choice->format : Format::ply;
  write_mesh(mesh, path, format, w);
}

Vec3 parse_point(const std::string& text, const std::string& what) {
  std::stringstream in(text);
  std::string part;
  std::vector<double> v;
  while (std::getline(in, part, ',')) v.push_back(parse_double(part, what));
  if (v.size() != 3) throw UsageError(what + " expects X,Y,Z, got '" + text + "'");
  const Vec3 p{v[0], v[1], v[2]};
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
    throw UsageError(what + " must be finite, got '" + text + "'");
  return p;
}

ProgressBar::ProgressBar(std::string label) : label_(std::move(label)), enabled_(::isatty(STDERR_FILENO) == 1) {}

ProgressBar::~ProgressBar() {
  if (enabled_ && last_percent_ >= 0) std::fprintf(stderr, "\r\033[K");
}

void ProgressBar::on_progress(double fraction) {
  if (!enabled_) return;
  const int percent = static_cast<int>(fraction * 100.0 + 0.5);
  if (percent == last_percent_) return;
  last_percent_ = percent;
  const int width = 40, filled = percent * width / 100;
  std::fprintf(stderr, "\r%s [%s%s] %3d%%", label_.c_str(), std::string(std::size_t(filled), '#').c_str(),
               std::string(std::size_t(width - filled), ' ').c_str(), percent);
  std::fflush(stderr);
}

}  // namespace visimp::app
