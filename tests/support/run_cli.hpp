#pragma once
// Running dmgplace and other programs from tests: argument vectors, never a shell, so a path
// needs no quoting and no character in it means anything. Header-only because it needs
// dmgplace_tools, which only some test programs link (test_support.cpp is in all of them).
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "dmgplace/tools/system/process.hpp"
#include "test_support.hpp"

namespace dmgplace::test {

using tools::ProcessOptions;
using tools::ProcessResult;
using tools::StderrTo;

// One command-line argument: text, or a path exactly as it is.
struct Arg {
  Arg(const char* s) : text(s) {}
  Arg(std::string s) : text(std::move(s)) {}
  Arg(const std::filesystem::path& p) : text(p.string()) {}
  std::string text;
};

// `dmgplace ARGS...`, its stdout and stderr captured together ("2>&1"), or only stdout with
// stderr dropped when `merge_stderr` is false.
inline ProcessResult run_cli(const std::vector<Arg>& args, bool merge_stderr = true) {
  std::vector<std::string> argv{cli_path()};
  for (const Arg& a : args) argv.push_back(a.text);
  ProcessOptions o;
  o.stderr_to = merge_stderr ? StderrTo::merge : StderrTo::discard;
  return tools::run_process(argv, o);
}

}  // namespace dmgplace::test
