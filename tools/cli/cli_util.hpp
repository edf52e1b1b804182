#pragma once
// Helpers shared by the subcommands: creation-parameter JSON, input hashing, what was written.
#include <algorithm>
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "dmgplace/formats/artifact_header.hpp"

namespace dmgplace::cli {

// A header for a new artifact: parameters as JSON, a SHA-256 of each input file: those named on
// the command line, then every other file the bake read (`read`, from an InputLog).
formats::ArtifactHeader make_header(const nlohmann::json& parameters, const std::vector<std::filesystem::path>& inputs,
                                    const std::vector<std::filesystem::path>& read = {});
// An artifact's summary, typed (inspect --json): counts and sizes as numbers, bounds as arrays.
nlohmann::ordered_json artifact_json(const std::filesystem::path& path);
// Prints "wrote PATH" plus the artifact's one-line summary; with `json`, one JSON object:
// {"written", "seconds", "artifact": artifact_json}.
// `extra` (JSON only) adds keys before "artifact".
void report_written(const std::filesystem::path& path, bool json = false, double seconds = 0,
                    const nlohmann::ordered_json& extra = nlohmann::ordered_json::object());
// "a,b,c" -> exactly n finite numbers, or dmgplace::Error naming the flag.
std::vector<double> parse_numbers(const std::string& text, std::size_t n, const std::string& flag);
template <std::size_t N>
std::array<double, N> parse_numbers(const std::string& text, const std::string& flag) {
  const auto v = parse_numbers(text, N, flag);
  std::array<double, N> out{};
  std::copy(v.begin(), v.end(), out.begin());
  return out;
}

}  // namespace dmgplace::cli
