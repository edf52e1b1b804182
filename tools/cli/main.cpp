// The dmgplace command line: global options, then one subcommand (subcommands.cpp) run with error
// handling. With subcommands.cpp, the only code that sees CLI11.
#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "cli_log.hpp"
#include "dmgplace/formats/artifact_header.hpp"
#include "dmgplace/formats/error.hpp"
#include "subcommands.hpp"

int main(int argc, char** argv) {
  using namespace dmgplace::cli;
  CLI::App app{"dmgplace: placement planning with in-hand regrasping (Dexterous Manipulation Graphs)"};
  app.set_version_flag("--version", dmgplace::formats::tool_version());
  app.require_subcommand(1);
  // Messages on stderr for every command (results stay on stdout): cli_log.hpp.
  std::string log_level = "info";
  bool verbose = false, quiet = false;
  app.add_option("--log-level", log_level, "Messages on stderr: trace, debug, info, warning, error, off")
      ->check(CLI::IsMember({"trace", "debug", "info", "warning", "warn", "error", "off"}))
      ->capture_default_str();
  app.add_flag("-v,--verbose", verbose, "Debug messages too (--log-level debug)");
  app.add_flag("-q,--quiet", quiet, "Warnings and errors only (--log-level warning)");
  app.fallthrough();
  app.footer(
      "Exit codes: 0 done; 1 bad input or failure (the message names the file, element and reason); "
      "3 no solution (place, plan); 103-114 a malformed command line (CLI11).");

  const std::vector<Subcommand> subcommands = add_subcommands(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  init_logging(quiet ? "warning" : verbose ? "debug" : log_level);

  try {
    for (const Subcommand& s : subcommands)
      if (*s.app) return s.run();
  } catch (const dmgplace::Error& e) {
    log_error(e.what());
    return 1;
  } catch (const std::exception& e) {
    log_error(std::string("unexpected failure: ") + e.what());
    return 1;
  }
  return 0;
}
