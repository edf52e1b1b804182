#include "cli_log.hpp"

#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cstdio>
#include <iostream>

namespace dmgplace::cli {
namespace {

std::shared_ptr<spdlog::logger>& logger() {
  static std::shared_ptr<spdlog::logger> l = [] {
    auto made = spdlog::stderr_logger_mt("dmgplace");
    made->set_pattern("%v");  // the messages carry their own "warning: " / "error: "
    made->set_level(spdlog::level::info);
    made->flush_on(spdlog::level::trace);  // stderr lines appear as they are written
    return made;
  }();
  return l;
}

// An ostream that drops everything (progress below info level).
class NullBuffer : public std::streambuf {
 protected:
  int overflow(int c) override { return c; }
};

}  // namespace

void init_logging(const std::string& level) {
  logger()->set_level(spdlog::level::from_str(level == "warn" ? "warning" : level));
}

bool logging_enabled_for_info() { return logger()->should_log(spdlog::level::info); }

void log_debug(const std::string& m) { logger()->debug(m); }
void log_info(const std::string& m) { logger()->info(m); }
void log_warning(const std::string& m) { logger()->warn("warning: " + m); }
void log_error(const std::string& m) { logger()->error("error: " + m); }

bool show_progress() { return logging_enabled_for_info() && isatty(STDERR_FILENO); }

std::function<void(const std::string&, std::size_t, std::size_t)> progress_line() {
  if (!show_progress()) return {};
  return [](const std::string& stage, std::size_t done, std::size_t total) {
    std::fprintf(stderr, "\r%s: %zu of %zu (%.0f%%)%s", stage.c_str(), done, total,
                 total ? 100.0 * double(done) / double(total) : 100.0, done >= total ? "\n" : "");
  };
}

std::ostream& progress_stream() {
  static NullBuffer null_buffer;
  static std::ostream null_stream(&null_buffer);
  return logging_enabled_for_info() ? std::cerr : null_stream;
}

}  // namespace dmgplace::cli
