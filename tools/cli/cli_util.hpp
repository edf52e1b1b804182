#pragma once
// Helpers shared by the subcommands: creation-parameter JSON and input hashing.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "dmgplace/formats/artifact_header.hpp"

namespace dmgplace::cli {

// A header for a new artifact: parameters as JSON, a SHA-256 of each input file.
formats::ArtifactHeader make_header(const nlohmann::json& parameters, const std::vector<std::filesystem::path>& inputs);
// Prints "wrote PATH" plus the artifact's one-line summary.
void report_written(const std::filesystem::path& path);

}  // namespace dmgplace::cli
