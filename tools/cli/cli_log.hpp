#pragma once
// The command line's messages on stderr, through spdlog: `--log-level`, `-v` (debug) and `-q`
// (warnings and errors only) on every command. Results go to stdout, never through here. The
// libraries print nothing; they report through return values and callbacks.
#include <cstddef>
#include <functional>
#include <ostream>
#include <string>

namespace dmgplace::cli {

// "trace", "debug", "info", "warning", "error", "off" (as --log-level takes them).
void init_logging(const std::string& level);
bool logging_enabled_for_info();

void log_debug(const std::string& message);
void log_info(const std::string& message);
void log_warning(const std::string& message);  // printed as "warning: MESSAGE"
void log_error(const std::string& message);    // printed as "error: MESSAGE"

// Progress lines redrawn in place: only on a terminal and at info level or below.
bool show_progress();
// A tools::ProgressFn drawing "STAGE: N of M (P%)" in place on stderr when show_progress(), else
// nothing (include "dmgplace/tools/system/progress.hpp" to name the type).
std::function<void(const std::string&, std::size_t, std::size_t)> progress_line();
// Where progress reports written as text go: stderr at info level, a sink that drops them below.
std::ostream& progress_stream();

}  // namespace dmgplace::cli
