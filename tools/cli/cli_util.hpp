#pragma once
// Helpers shared by the subcommands: creation-parameter JSON, input hashing, what was written.
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
void report_written(const std::filesystem::path& path, bool json = false, double seconds = 0);

}  // namespace dmgplace::cli
