#pragma once
// Running other programs without a shell. The program and its arguments reach the kernel as an
// argument vector (posix_spawnp), so nothing in a path or a name is ever interpreted: no quoting,
// no word splitting, no $(...). dmgplace starts every other program through this.
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace dmgplace::tools {

// Where the child's standard error goes.
enum class StderrTo {
  inherit,  // this process's stderr (the default: a tool's messages stay visible)
  merge,    // into ProcessResult::output, interleaved with stdout as written ("2>&1")
  capture,  // into ProcessResult::error_output, apart from stdout
  discard,  // /dev/null
};

struct ProcessOptions {
  std::optional<std::string> input;                      // written to the child's stdin; none: stdin reads /dev/null
  std::filesystem::path cwd;                             // the child's working directory; empty: this process's
  std::vector<std::pair<std::string, std::string>> env;  // NAME=VALUE set on top of this process's environment
  StderrTo stderr_to = StderrTo::inherit;
};

struct ProcessResult {
  int exit_code = -1;        // the exit status, -1 when a signal ended the child
  int signal = 0;            // the signal that ended it, 0 when it exited
  std::string output;        // its stdout (and stderr with StderrTo::merge)
  std::string error_output;  // its stderr with StderrTo::capture
};

// Runs argv[0] with arguments argv[1..] and waits for it. argv[0] without a '/' is looked up in
// $PATH; a relative one with a '/' is taken from this process's working directory, not from
// `options.cwd`. Throws dmgplace::Error naming the program when it cannot be started (not found,
// not executable, bad cwd); a program that starts and fails is reported by exit_code instead.
ProcessResult run_process(const std::vector<std::string>& argv, const ProcessOptions& options = {});

// The executable file `name` would run as, searched in $PATH as a shell's `command -v` does
// (a name with a '/' is checked as it is); nullopt when there is none.
std::optional<std::filesystem::path> find_executable(const std::string& name);

}  // namespace dmgplace::tools
