#pragma once
// The command line's messages on stderr, through spdlog: `--log-level`, `-v` (debug) and `-q`
// (warnings and errors only) on every command. Results go to stdout, never through here. The
// libraries print nothing; they report through return values and callbacks.
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
// Where progress reports written as text go: stderr at info level, a sink that drops them below.
std::ostream& progress_stream();

}  // namespace dmgplace::cli
