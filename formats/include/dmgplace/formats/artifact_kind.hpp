#pragma once
// The pieces each artifact kind provides: its schema, a semantic check and a summary.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace dmgplace::formats {

using Summary = std::vector<std::pair<std::string, std::string>>;  // ordered key -> value

// `dmgplace batch-collect`'s dataset (layout: tools/include/dmgplace/tools/batch/batch_report.hpp).
inline constexpr const char* kDatasetSchema = "dmgplace.dataset";
inline constexpr int kDatasetSchemaVersion = 2;

// Checks one artifact file of any known kind: header, schema, every checksum, then the kind's
// semantic invariants. Returns one line per problem (empty when the file is sound).
std::vector<std::string> validate_artifact(const std::filesystem::path& path);
// Loads any known kind and summarises it (counts, bounds, parameters). Throws dmgplace::Error.
Summary inspect_artifact(const std::filesystem::path& path);

}  // namespace dmgplace::formats
